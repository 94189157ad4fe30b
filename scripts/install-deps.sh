#!/usr/bin/env bash
# Installs, only when missing, every Debian package asperity needs to build and test.
# Idempotent: a machine that already has them all is left untouched (no apt-get at all).
# With --test, also the tools the tests drive: GNU parallel (a job runner for terrain plans)
# and gdal-bin (gdalinfo and gdal_translate open the plans' mosaics).
set -euo pipefail

packages=(
  build-essential cmake pkg-config
  libopenmesh-dev libcgal-dev libeigen3-dev libgmp-dev libmpfr-dev libboost-dev
  python3-venv
)
if [ "${1:-}" = "--test" ]; then
  packages+=(parallel gdal-bin)
fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} Debian packages present"
  exit 0
fi

if [ "$(id -u)" -eq 0 ]; then
  sudo=()
elif command -v sudo >/dev/null 2>&1; then
  sudo=(sudo)
else
  echo "install-deps: missing ${missing[*]}; run this script as root (sudo is not available)" >&2
  exit 1
fi

echo "install-deps: installing ${missing[*]}"
"${sudo[@]}" apt-get update -qq
DEBIAN_FRONTEND=noninteractive "${sudo[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
echo "install-deps: done"
