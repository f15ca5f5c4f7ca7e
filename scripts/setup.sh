#!/usr/bin/env bash
# Installs the Debian 12 packages Lobe builds with. Idempotent: when every package is present it
# returns in well under a second without touching apt. Needs root (or sudo) only to install.
set -euo pipefail

packages=(
  build-essential cmake pkg-config ccache
  libembree-dev libopenvdb-dev libnanovdb-dev libboost-iostreams-dev
  libopenimageio-dev openimageio-tools libtbb-dev libimath-dev libjpeg-dev
  libgtest-dev libgmock-dev libbenchmark-dev libcli11-dev nlohmann-json3-dev zlib1g-dev
  libhwy-dev
  libgdcm-dev python3-pydicom python3-nibabel mricron-data
  fonts-dejavu-core libfreetype-dev
  openmpi-bin libopenmpi-dev
  clang libclang-rt-14-dev bc clang-format
  # the VTK comparison (bench/peers/run.sh), run with /usr/bin/python3
  python3-vtk9 xvfb xauth python3-numpy python3-scipy python3-nibabel python3-openimageio
  # the Python module (python/, built against /usr/bin/python3) and its walk-through (docs/python.md)
  pybind11-dev python3-dev python3-matplotlib
  # lobe study: its server, and the real-browser test
  libcpp-httplib-dev chromium chromium-driver python3-selenium
)

missing=()
for p in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)
  [[ "$status" == "install ok installed" ]] || missing+=("$p")
done
if [[ ${#missing[@]} -eq 0 ]]; then
  exit 0
fi

echo "setup: installing ${#missing[@]} Debian packages: ${missing[*]}"
sudo_cmd=()
if [[ $(id -u) -ne 0 ]]; then
  command -v sudo >/dev/null || { echo "setup: need root or sudo to install packages" >&2; exit 1; }
  sudo_cmd=(sudo)
fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "setup: done"
