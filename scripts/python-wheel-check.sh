#!/usr/bin/env bash
# Installs the manylinux wheel (scripts/python-wheel.sh) into a fresh virtual environment
# and runs the package's tests there as a machine without the Debian packages would: in a
# mount namespace where the system's OpenMesh and GMP libraries are covered by empty files,
# with LD_LIBRARY_PATH empty. The tests that compare with the command line (which links
# the system's libraries) ran against the same wheel before and are skipped here. Also
# checks that the extension loads its libraries from the wheel's asperity.libs/.
# Usage: scripts/python-wheel-check.sh WHEEL
set -euo pipefail
cd "$(dirname "$0")/.."
wheel=${1:?usage: scripts/python-wheel-check.sh WHEEL}
venv=target/wheel-check-venv
rm -rf "$venv"
python3 -m venv "$venv"
"$venv/bin/python" -m pip install -q --disable-pip-version-check "$wheel" pytest trimesh

# The libraries the wheel bundles, as the system has them (resolved through /lib's symlinks).
hidden=()
for pattern in 'libOpenMesh*.so*' 'libgmp.so*'; do
  while IFS= read -r f; do hidden+=("$(readlink -f "$f")"); done \
    < <(find /usr/lib /lib -maxdepth 2 -name "$pattern" 2>/dev/null)
done
mapfile -t hidden < <(printf '%s\n' "${hidden[@]}" | sort -u)
[ ${#hidden[@]} -gt 0 ] || { echo "python-wheel-check: no system OpenMesh or GMP library found to hide" >&2; exit 1; }

# Which files the import loads, from the dynamic loader's own trace.
loaded=$(LD_LIBRARY_PATH= LD_DEBUG=libs "$venv/bin/python" -c 'import asperity' 2>&1 | sed -n 's/.*calling init: //p')
for lib in libOpenMeshCore libOpenMeshTools libgmp; do
  grep -q "asperity.libs/$lib-" <<<"$loaded" \
    || { echo "python-wheel-check: $lib not loaded from the wheel's asperity.libs:"$'\n'"$loaded" >&2; exit 1; }
done
if echo "$loaded" | grep -E '^/(usr/)?lib.*/lib(OpenMesh|gmp)'; then
  echo "python-wheel-check: a system copy of a bundled library was loaded" >&2
  exit 1
fi

# The tests, with the system's copies hidden.
script='for f in "$@"; do mount --bind /dev/null "$f"; done
for f in "$@"; do [ ! -s "$f" ] || { echo "python-wheel-check: could not hide $f" >&2; exit 1; }; done
LD_LIBRARY_PATH= ASPERITY_NO_CLI=1 '"$venv"'/bin/python -m pytest -q -p no:cacheprovider python/tests'
if unshare --mount --map-root-user true 2>/dev/null; then
  unshare --mount --map-root-user bash -c "$script" hide "${hidden[@]}"
  echo "python-wheel-check: $(basename "$wheel") passed its tests with ${#hidden[@]} system libraries hidden"
else
  echo "python-wheel-check: this machine refuses a mount namespace (unshare): the tests run with the system's libraries present; the loader trace above showed none of them loaded" >&2
  LD_LIBRARY_PATH= ASPERITY_NO_CLI=1 "$venv/bin/python" -m pytest -q -p no:cacheprovider python/tests
fi
