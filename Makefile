# asperity — the two commands: `make demo` and `make test`.
CARGO ?= cargo

.PHONY: all deps build demo test clippy clean

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
	$(CARGO) test --all-targets
	$(CARGO) clippy --all-targets -- -D warnings

clippy: deps
	$(CARGO) clippy --all-targets -- -D warnings

clean:
	$(CARGO) clean
	rm -rf out
