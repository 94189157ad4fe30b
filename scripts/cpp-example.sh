#!/usr/bin/env bash
# Builds and installs the C++ package (cpp/, -DASPERITY_PACKAGE=ON) into target/cpp-install,
# then builds examples/cpp against it with find_package(asperity) and runs it.
# PROFILE=dev (the default here, sharing `cargo test`'s build) or PROFILE=release.
set -euo pipefail
cd "$(dirname "$0")/.."
profile=${PROFILE:-dev}
root=$PWD
# In the dev profile, build as `cargo test` does (workspace libraries and tests, so features
# resolve alike): the library `cargo test` compiled is reused, not compiled again.
packages="-p;asperity-cxx"
[ "$profile" = dev ] && packages="--workspace;--lib;--tests;--features;asperity/cli"
cmake -S cpp -B target/cpp-package -DASPERITY_PACKAGE=ON -DASPERITY_CARGO_PROFILE="$profile" \
  -DASPERITY_CARGO_PACKAGES="$packages" \
  -DCMAKE_INSTALL_PREFIX="$root/target/cpp-install" >/dev/null
cmake --build target/cpp-package
cmake --install target/cpp-package >/dev/null
# Each installed header compiles alone after only OpenMesh's kernel header, as a user's file
# includes it (#36: terrain.hpp used color_cast without including it).
for header in target/cpp-install/include/asperity/*.hpp; do
  name=$(basename "$header")
  [ "$name" = bridge.rs.h ] && continue
  printf '#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>\n#include <asperity/%s>\n' "$name" |
    g++ -std=c++17 -fsyntax-only -I target/cpp-install/include -x c++ - ||
    { echo "cpp-example: asperity/$name does not compile alone after TriMesh_ArrayKernelT.hh" >&2; exit 1; }
done
cmake -S examples/cpp -B target/cpp-example -DCMAKE_PREFIX_PATH="$root/target/cpp-install" >/dev/null
cmake --build target/cpp-example
mkdir -p target/cpp-example/out
# An empty MESH argument means "the built-in sphere".
./target/cpp-example/openmesh_pipeline "" target/cpp-example/out
./target/cpp-example/integration target/cpp-example/out

# The same integration example against the shared library, built with pkg-config alone.
pc=target/cpp-install/lib/pkgconfig
[ -f "$pc/asperity.pc" ] || pc=$(dirname "$(find target/cpp-install -name asperity.pc | head -1)")
# shellcheck disable=SC2046 # pkg-config's output is words by design
g++ -std=c++17 -O1 examples/cpp/integration.cpp -o target/cpp-example/integration-shared \
  $(PKG_CONFIG_PATH="$pc" pkg-config --cflags --libs asperity)
libdir=$(PKG_CONFIG_PATH="$pc" pkg-config --variable=libdir asperity)
# ldd's output is read whole before matching: `ldd | grep -q` under pipefail fails at random
# when grep exits at the first match and ldd is killed by SIGPIPE writing the lines after it.
linked=$(LD_LIBRARY_PATH="$libdir" ldd target/cpp-example/integration-shared)
grep -q "libasperity.so.0 => $libdir" <<<"$linked" \
  || { echo "cpp-example: the pkg-config build does not use $libdir/libasperity.so.0:" >&2
       echo "$linked" >&2; exit 1; }
mkdir -p target/cpp-example/out-shared
LD_LIBRARY_PATH="$libdir" ./target/cpp-example/integration-shared target/cpp-example/out-shared
