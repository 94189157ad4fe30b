#!/usr/bin/env bash
# Builds and installs the Python package (python/, PyO3 + maturin) into a virtual
# environment the project creates: target/python-venv, or $ASPERITY_VENV. With --test, also
# pytest and the optional packages the tests use when they install (trimesh, matplotlib).
# Needs the Debian packages of scripts/install-deps.sh (make python runs it first).
set -euo pipefail
cd "$(dirname "$0")/.."
venv="${ASPERITY_VENV:-target/python-venv}"
if [ ! -x "$venv/bin/python" ]; then
  python3 -m venv "$venv"
fi
"$venv/bin/python" -m pip install -q --upgrade pip
"$venv/bin/python" -m pip install -q ./python
if [ "${1:-}" = "--test" ]; then
  "$venv/bin/python" -m pip install -q pytest
  "$venv/bin/python" -m pip install -q trimesh matplotlib \
    || echo "python-package: trimesh or matplotlib did not install: the tests that use them are skipped"
fi
echo "python-package: $("$venv/bin/python" -c 'import asperity; print("asperity", asperity.__version__, "in", asperity.__file__)')"
