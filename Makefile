# asperity — the two commands: `make demo` and `make test`.
CARGO ?= cargo

.PHONY: all deps build demo figures test clippy doc bench clean install-cpp fuzz sanitize python python-test wheel

all: build

# Debian packages (idempotent: the script does nothing when all are present).
deps:
	@./scripts/install-deps.sh

# The command line is the library's `cli` feature (off for library users, #38).
build: deps
	$(CARGO) build --release --features cli

# The main job on built-in inputs: meshes and previews under out/.
demo: build
	./target/release/asperity demo --out out

# The thesis' figures as we reproduce them, with the thesis' captions (docs/figures.md).
figures: build
	./scripts/figures.sh

# The tests select the whole workspace with the command line (`asperity/cli`: the integration
# tests drive the binary), as the C++ and Python builds after them do: features then resolve
# alike (the Python crate's proc-macros turn on syn features), so those builds reuse this
# one instead of compiling every crate again (6 minutes of CI).
test: deps
	@./scripts/install-deps.sh --test
	@./scripts/install-gltf-validator.sh
	@./scripts/fetch-test-meshes.sh
	$(CARGO) test --workspace --features asperity/cli
	@./scripts/cpp-example.sh
	@$(MAKE) --no-print-directory python-test
	@$(MAKE) --no-print-directory clippy
	@$(MAKE) --no-print-directory doc

# The Python package in a virtual environment of its own (target/python-venv): the manylinux
# wheel of `make wheel` installed there, then `import asperity` from any folder with that
# environment's python.
python: deps
	./scripts/python-package.sh

# pytest over python/tests, against the command line's binary for the identity tests (the
# one `cargo test` built; any build gives the same bits); then the same wheel in a fresh
# environment with the system's OpenMesh and GMP hidden.
python-test: deps
	@./scripts/python-package.sh --test
	@[ -x target/debug/asperity ] || $(CARGO) build --bin asperity --features cli
	ASPERITY_CLI=target/debug/asperity target/python-venv/bin/python -m pytest -q python/tests
	@./scripts/python-wheel-check.sh target/wheels/manylinux/*.whl

# The Python package as a manylinux wheel with OpenMesh and GMP bundled, in
# target/wheels/manylinux/ (pip install it on any x86-64 Linux with glibc >= 2.35).
wheel: deps
	./scripts/python-wheel.sh

# API documentation, private items included; a broken link fails the tests.
doc:
	RUSTDOCFLAGS="-D warnings" $(CARGO) doc --no-deps --workspace --features asperity/cli --document-private-items

# The C++ package (find_package(asperity)) into PREFIX, optimised.
PREFIX ?= /usr/local
install-cpp: deps
	cmake -S cpp -B target/cpp-release -DASPERITY_PACKAGE=ON -DCMAKE_INSTALL_PREFIX=$(PREFIX)
	cmake --build target/cpp-release
	cmake --install target/cpp-release

# Lints are part of the tests where clippy is installed; the library is also linted without
# its `cli` feature (what a library user gets by default: no clap).
clippy: deps
	@if $(CARGO) clippy --version >/dev/null 2>&1; then \
	  $(CARGO) clippy --workspace --all-targets --features asperity/cli -- -D warnings && \
	  $(CARGO) clippy -p asperity --lib -- -D warnings; \
	else echo "clippy not installed: lints skipped"; fi

# Each cargo-fuzz target for FUZZ_SECONDS (default 60) on nightly; crashes are saved under
# tests/data/fuzz/, which cargo test replays.
fuzz: deps
	./scripts/fuzz.sh

# The C++ adapter and the test binaries with AddressSanitizer + UBSan, then the test suite
# (own target folder: target/sanitize).
sanitize: deps
	./scripts/sanitize.sh

bench: deps
	$(CARGO) bench

clean:
	$(CARGO) clean
	rm -rf out
