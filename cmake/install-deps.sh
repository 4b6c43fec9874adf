#!/usr/bin/env bash
# Install what spectralize needs, by purpose (the first argument):
#   demo     what `make demo` builds and runs: the compiler, the libraries of the tool, the
#            plugin and the Python module, a font for plots, and Mitsuba 3 for its render;
#   install  what `make install` builds: the demo's, and Sphinx for the guide it installs;
#   test     (the default) everything: the above, GoogleTest and Benchmark, clang-format,
#            pytest, Slurm and munge, Chromium, debootstrap for the sid lane.
# The Debian packages, then the pinned Python packages of cmake/python-requirements.txt (PyPI)
# into a virtual environment that also sees Debian's packages ($SPECTRALIZE_VENV, default
# ~/.cache/spectralize/venv), for the demo and the tests.
# Idempotent: checks with dpkg first and with a stamp of the requirements in the environment,
# so it returns in well under a second when all are present.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
purpose=${1:-test}

demo_packages=(
  cmake make g++ pkg-config
  libopenimageio-dev openimageio-tools
  libopencolorio-dev opencolorio-tools
  libopenexr-dev libimath-dev openexr
  libfmt-dev nlohmann-json3-dev libeigen3-dev liblcms2-dev
  fonts-dejavu-core
  python3 python3-dev pybind11-dev python3-numpy python3-openimageio
  python3-venv libllvm19
)
install_packages=(
  python3-sphinx python3-myst-parser python3-sphinx-rtd-theme
)
test_packages=(
  libgtest-dev libgmock-dev libbenchmark-dev
  clang-format
  slurmctld slurmd slurm-client munge
  python3-pytest python3-matplotlib
  man-db groff-base
  chromium python3-websocket
  debootstrap
)
case "$purpose" in
  demo) packages=("${demo_packages[@]}") ;;
  install) packages=("${demo_packages[@]}" "${install_packages[@]}") ;;
  test) packages=("${demo_packages[@]}" "${install_packages[@]}" "${test_packages[@]}") ;;
  *) echo "install-deps: unknown purpose '$purpose' (demo, install or test)" >&2; exit 2 ;;
esac

# HEIF's encoders: libheif 1.16 and later (Debian 13, sid) ship them as plugins of their own
# (Debian 12's libheif 1.15 has them built in), which OIIO's HEIF writer needs. Decided by the
# installed libheif, so that a run with everything present stays quick.
heif_plugins() {
  local v
  v=$(dpkg-query -W -f='${Version}' libheif1 2>/dev/null || true)
  if [ -n "$v" ] && dpkg --compare-versions "$v" ge 1.16; then
    echo libheif-plugin-x265 libheif-plugin-aomenc
  fi
}

missing_of() {
  local p
  for p in "$@"; do
    if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
      echo "$p"
    fi
  done
}

# The virtual environment: Debian's interpreter (the one the module is built for), its packages
# visible, the pinned ones from PyPI. Remade when the interpreter or the requirements change.
python_packages() {
  local venv=${SPECTRALIZE_VENV:-${HOME:-/root}/.cache/spectralize/venv}
  local requirements="$here/python-requirements.txt" stamp want
  want="$(/usr/bin/python3 --version) $(sha256sum "$requirements" | cut -d' ' -f1)"
  stamp="$venv/.spectralize-requirements"
  if [ -f "$stamp" ] && [ "$(cat "$stamp")" = "$want" ] && [ -x "$venv/bin/python" ]; then
    return 0
  fi
  echo "install-deps: Python packages into $venv"
  rm -rf "$venv"
  /usr/bin/python3 -m venv --system-site-packages "$venv"
  "$venv/bin/python" -m pip install -q --disable-pip-version-check -r "$requirements"
  echo "$want" >"$stamp"
}

# HEIF's encoders only for the tests (the HEIF output cases); the demo writes none.
heif=()
# shellcheck disable=SC2207
[ "$purpose" = test ] && heif=($(heif_plugins))
# shellcheck disable=SC2207
missing=($(missing_of "${packages[@]}" "${heif[@]}"))
if [ ${#missing[@]} -eq 0 ]; then
  [ "$purpose" = install ] || python_packages
  exit 0
fi

sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then
  sudo_cmd=(sudo)
fi
export DEBIAN_FRONTEND=noninteractive
install() {
  echo "install-deps: installing $*"
  "${sudo_cmd[@]}" apt-get update -qq
  "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "$@" >/dev/null
}
install "${missing[@]}"
if [ "$purpose" = test ]; then
  # libheif arrives with OpenImageIO: its plugins are known only now.
  # shellcheck disable=SC2207
  late=($(missing_of $(heif_plugins)))
  [ ${#late[@]} -eq 0 ] || install "${late[@]}"
fi
[ "$purpose" = install ] || python_packages
echo "install-deps: done"
