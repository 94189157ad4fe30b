#!/usr/bin/env bash
# Peak memory and throughput of streamed terrains (issues #4, #23: 65537² within 100 MB): 16 385² and 65 537² classic
# grids written as RAW16 to /dev/null, measured with GNU time. Run after `make build`.
set -euo pipefail
cd "$(dirname "$0")/.."
bin=target/release/asperity
[ -x "$bin" ] || cargo build --release --features cli
for size in 16385 65537; do
  /usr/bin/time -f "peak RSS %M KB, wall %e s" "$bin" terrain --size "$size" --seed 1 --stream --format raw16 -o /dev/null 2>&1 | sed "s/^/$size: /" || true
done
