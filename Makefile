# asperity — the two commands: `make demo` and `make test`.
CARGO ?= cargo

.PHONY: all deps build demo test clippy bench clean

all: build

# Debian packages (idempotent: the script does nothing when all are present).
deps:
	@./scripts/install-deps.sh

build: deps
	$(CARGO) build --release

# The main job on built-in inputs: meshes and previews under out/.
demo: build
	./target/release/asperity demo --out out

test: deps
	@./scripts/install-gltf-validator.sh
	$(CARGO) test
	@$(MAKE) --no-print-directory clippy

# Lints are part of the tests where clippy is installed.
clippy: deps
	@if $(CARGO) clippy --version >/dev/null 2>&1; then \
	  $(CARGO) clippy --all-targets -- -D warnings; \
	else echo "clippy not installed: lints skipped"; fi

bench: deps
	$(CARGO) bench

clean:
	$(CARGO) clean
	rm -rf out
