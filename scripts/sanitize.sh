#!/bin/sh
# `make sanitize`: the C++ adapter (OpenMesh/CGAL code in cpp/src) and the cxx bridge
# built with AddressSanitizer and UndefinedBehaviorSanitizer (gcc's runtimes), every test
# binary and the CLI linked with them, then the whole test suite run. Rust code itself is
# not instrumented (that needs nightly; it is memory-safe outside src/ffi.rs), but its heap
# goes through ASan's allocator, so a C++ overrun into Rust memory is caught too.
# A separate target folder keeps the ordinary build untouched.
set -eu
cd "$(dirname "$0")/.."
export ASPERITY_SANITIZE=${ASPERITY_SANITIZE:-address,undefined}
export CARGO_TARGET_DIR=${CARGO_TARGET_DIR:-target/sanitize}
# Any report ends the run with a non-zero status; leaks are reported too.
export ASAN_OPTIONS=${ASAN_OPTIONS:-abort_on_error=0:halt_on_error=1:detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$(pwd)/scripts/lsan.supp:print_suppressions=0}
cargo test -p asperity --features cli "$@"
