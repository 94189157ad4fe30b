#!/usr/bin/env bash
# The real meshes the tests use. They normally sit beside the checkout, in
# ../shared/data/meshes; where they do not (a fresh clone elsewhere), the same files are
# taken from Debian bookworm's libcgal-demo package (its data/meshes, CC0 — see
# ../shared/data/meshes/README.md) into target/test-meshes/data/meshes. Idempotent.
set -euo pipefail
cd "$(dirname "$0")/.."
MESHES="3torus anchor blade bunny00 double-torus-3-holes eight elephant fandisk femur mushroom"
if [ -d ../shared/data/meshes ]; then exit 0; fi
dest=target/test-meshes/data/meshes
missing=0
for m in $MESHES; do [ -f "$dest/$m.off" ] || missing=1; done
if [ "$missing" = 0 ]; then exit 0; fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
echo "fetch-test-meshes: ../shared/data/meshes is absent; taking the meshes from Debian's libcgal-demo"
(cd "$work" && apt-get download libcgal-demo >/dev/null 2>&1 || { apt-get update >/dev/null && apt-get download libcgal-demo; })
mkdir -p "$dest"
dpkg-deb --fsys-tarfile "$work"/libcgal-demo_*.deb | tar -xO ./usr/share/doc/libcgal-dev/data.tar.gz \
  | tar -xz -C "$work" data/meshes
for m in $MESHES; do cp "$work/data/meshes/$m.off" "$dest/$m.off"; done
