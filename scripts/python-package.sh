#!/usr/bin/env bash
# Builds the Python package (python/, PyO3 + maturin) as a manylinux wheel
# (scripts/python-wheel.sh) and installs it into a virtual environment the project creates:
# target/python-venv, or $ASPERITY_VENV. With --test, also
# pytest and the optional packages the tests use when they install (trimesh, matplotlib).
# Needs the Debian packages of scripts/install-deps.sh (make python runs it first).
set -euo pipefail
cd "$(dirname "$0")/.."
venv="${ASPERITY_VENV:-target/python-venv}"
if [ ! -x "$venv/bin/python" ]; then
  python3 -m venv "$venv"
fi
"$venv/bin/python" -m pip install -q --upgrade pip
# The manylinux wheel `make wheel` ships (its native libraries bundled), not a build of its
# own: what the tests pass on is what users install.
# With --test, the dev profile: the tests' build shares what `cargo test` compiled.
[ "${1:-}" = "--test" ] && export ASPERITY_WHEEL_PROFILE=${ASPERITY_WHEEL_PROFILE:-dev}
wheel=$(./scripts/python-wheel.sh)
"$venv/bin/python" -m pip install -q "$wheel"
"$venv/bin/python" -m pip install -q --force-reinstall --no-deps "$wheel"
if [ "${1:-}" = "--test" ]; then
  "$venv/bin/python" -m pip install -q pytest
  "$venv/bin/python" -m pip install -q trimesh matplotlib \
    || echo "python-package: trimesh or matplotlib did not install: the tests that use them are skipped"
fi
echo "python-package: $("$venv/bin/python" -c 'import asperity; print("asperity", asperity.__version__, "in", asperity.__file__)')"
