#!/usr/bin/env bash
# Refreshes the README gallery (docs/gallery/) from `asperity demo`'s pictures.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release -q --features cli
./target/release/asperity demo --out target/gallery-demo --quiet
mkdir -p docs/gallery
for picture in noise-panel terrain-map terrain terrain-views terrain-dual terrain-smooth-map terrain-eroded clouds \
  fandisk-features fandisk-hierarchy detail-torus-variation detail-sphere-marble detail-sphere-turbulence \
  detail-sphere-multifractal detail-sphere-wood detail-mushroom-planet detail-sphere-virus detail-femur-wearing detail-femur-wearing-strong \
  detail-fandisk-erosion detail-elephant-taper-twist detail-bunny-hair scene scene-generators; do
  cp "target/gallery-demo/$picture.png" docs/gallery/
done
du -ch docs/gallery/*.png | tail -1
