#!/usr/bin/env bash
# Install the Debian packages spectralize builds and tests with.
# Idempotent: checks with dpkg first, so it returns in well under a second when all are present.
set -euo pipefail

packages=(
  cmake make g++ pkg-config
  libopenimageio-dev openimageio-tools
  libopencolorio-dev opencolorio-tools
  libopenexr-dev libimath-dev openexr
  libfmt-dev libgtest-dev libgmock-dev libbenchmark-dev
  nlohmann-json3-dev libeigen3-dev liblcms2-dev
  clang-format
  fonts-dejavu-core
  slurmctld slurmd slurm-client munge
  python3 python3-dev pybind11-dev python3-numpy python3-pytest python3-openimageio
  python3-matplotlib
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

echo "install-deps: installing ${missing[*]}"
sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then
  sudo_cmd=(sudo)
fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "install-deps: done"
