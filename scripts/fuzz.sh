#!/bin/sh
# `make fuzz`: runs every cargo-fuzz target for FUZZ_SECONDS seconds (default 60), seeded
# with the hostile corpus, the recipes and earlier finds. Needs the nightly toolchain
# (not needed by `make test`); installs cargo-fuzz when missing. A crash is copied to
# tests/data/fuzz/<target>/, where tests/io/fuzz_regressions.rs replays it from then on, and
# the script exits 1.
#   FUZZ_SECONDS=600 FUZZ_TARGETS="pipeline" make fuzz
set -eu
cd "$(dirname "$0")/.."
seconds=${FUZZ_SECONDS:-60}
targets=${FUZZ_TARGETS:-"read_obj read_ply read_off read_stl read_glb recipe pipeline"}

if ! rustup run nightly rustc --version >/dev/null 2>&1; then
  echo "fuzz: installing the nightly toolchain"
  rustup toolchain install nightly --profile minimal
fi
if ! cargo +nightly fuzz --version >/dev/null 2>&1; then
  echo "fuzz: installing cargo-fuzz"
  cargo install cargo-fuzz --locked
fi

# Seeds: files of the target's format from the hostile corpus and the tests, the recipes,
# and every saved regression.
seed() {
  target=$1 corpus=fuzz/corpus/$1
  mkdir -p "$corpus"
  case $target in
    read_*) ext=${target#read_}
            find tests/data -name "*.$ext" -size -256k -exec cp {} "$corpus/" \; ;;
    recipe) cp recipes/*.toml "$corpus/" ;;
    # A tetrahedron: 4 vertices (count byte 1), lattice coordinates (byte - 8), 4 faces.
    pipeline) printf '\001\010\010\010\011\010\010\010\011\010\010\010\011\000\002\001\000\001\003\000\003\002\001\002\003' > "$corpus/tetrahedron" ;;
  esac
  if [ -d "tests/data/fuzz/$target" ]; then cp "tests/data/fuzz/$target"/* "$corpus/" 2>/dev/null || true; fi
}

status=0
for target in $targets; do
  seed "$target"
  echo "fuzz: $target for ${seconds}s"
  if ! cargo +nightly fuzz run --fuzz-dir fuzz "$target" "fuzz/corpus/$target" -- \
      -max_total_time="$seconds" -rss_limit_mb=4096 -timeout=30 -max_len=65536 -print_final_stats=1; then
    mkdir -p "tests/data/fuzz/$target"
    for crash in fuzz/artifacts/"$target"/*; do
      [ -f "$crash" ] || continue
      cp "$crash" "tests/data/fuzz/$target/"
      echo "fuzz: $target failed on $crash, saved to tests/data/fuzz/$target/ (replayed by make test)"
    done
    status=1
  fi
done
exit $status
