#!/usr/bin/env bash
# make test-platform: runs a make target of this checkout (default: test) on Debian sid's stack
# (OpenImageIO 3.x, OpenColorIO 2.5, OpenEXR 3.4, GCC 16, CMake 4, Python 3.14) in a minimal
# chroot made with debootstrap from the mirror this machine's apt is configured with.
#
#   cmake/test-platform.sh [make target...]     e.g. test, demo, test-asan
#   cmake/test-platform.sh --sh 'COMMAND'          a shell command in the copy, e.g. for one test
#   cmake/test-platform.sh --prepare               only make the root and install the packages
#                                                  (CI does it while the Debian 12 lane builds)
#
# Needs root (debootstrap, chroot, bind mounts) and the Debian mirror apt uses. The root is
# cached outside the checkout ($SPECTRALIZE_PLATFORM_ROOT, default /var/cache/spectralize/sid):
# a second run skips debootstrap and installs only what is missing. The checkout (tracked and
# untracked files, not build trees) is copied to /work/spectralize inside the root, where its
# build tree stays between runs. Mounts are undone on every exit path.
set -euo pipefail

src=$(cd "$(dirname "$0")/.." && pwd)
root=${SPECTRALIZE_PLATFORM_ROOT:-/var/cache/spectralize/sid}
suite=${SPECTRALIZE_PLATFORM_SUITE:-sid}
shell_command=""
if [ "${1:-}" = "--sh" ]; then
  shell_command=${2:?--sh needs a command}
  shift 2
elif [ "${1:-}" = "--prepare" ]; then
  shell_command="bash cmake/install-deps.sh"
  shift
fi
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(test)

say() { echo "test-platform: $*"; }
die() { echo "test-platform: $*" >&2; exit 1; }

[ "$(id -u)" -eq 0 ] || die "needs root (debootstrap, chroot and bind mounts); run it as root"

# The mirror apt already uses: the first URIs: of a deb822 sources file, else the first deb line.
mirror() {
  local f uri=""
  for f in /etc/apt/sources.list.d/*.sources; do
    [ -f "$f" ] || continue
    uri=$(awk '/^URIs:/ {print $2; exit}' "$f")
    [ -n "$uri" ] && break
  done
  if [ -z "$uri" ] && [ -f /etc/apt/sources.list ]; then
    uri=$(awk '$1 == "deb" {for (i = 2; i <= NF; i++) if ($i ~ /:\/\//) {print $i; exit}}' \
      /etc/apt/sources.list)
  fi
  [ -n "$uri" ] || die "no Debian mirror in /etc/apt/sources.list.d/*.sources or /etc/apt/sources.list"
  echo "$uri"
}

mounted=()
unmount_all() {
  local i
  for ((i = ${#mounted[@]} - 1; i >= 0; i--)); do
    umount -l "${mounted[$i]}" 2>/dev/null || true
  done
  mounted=()
}
trap unmount_all EXIT
trap 'exit 130' INT
trap 'exit 143' TERM

bind() {  # bind <host path> <path in root>
  mkdir -p "$root$2"
  if ! mountpoint -q "$root$2"; then
    mount --rbind "$1" "$root$2"
    mount --make-rslave "$root$2"
    mounted+=("$root$2")
  fi
}

make_root() {
  command -v debootstrap >/dev/null || {
    say "installing debootstrap"
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends debootstrap >/dev/null
  }
  local uri partial="$root.partial"
  uri=$(mirror)
  say "making a minimal $suite root in $root from the configured mirror (about a minute)"
  rm -rf "$partial"
  mkdir -p "$(dirname "$root")"
  debootstrap --variant=minbase "$suite" "$partial" "$uri" >"$partial.log" 2>&1 ||
    die "debootstrap failed; its log is $partial.log"
  # The mirror's Release files may be past their Valid-Until date.
  echo 'Acquire::Check-Valid-Until "false";' >"$partial/etc/apt/apt.conf.d/99spectralize"
  echo 'APT::Install-Recommends "false";' >>"$partial/etc/apt/apt.conf.d/99spectralize"
  rm -rf "$root"
  mv "$partial" "$root"
  rm -f "$partial.log"
  touch "$root/.spectralize-root"
}

[ -f "$root/.spectralize-root" ] || make_root
cp -L /etc/resolv.conf "$root/etc/resolv.conf" 2>/dev/null || true
# pip in the root (the pinned Python packages) trusts what this machine trusts: its CA bundle
# (pip's own, $PIP_CERT, or the system's), and takes this machine's pip settings ($PIP_*).
host_ca=${PIP_CERT:-${REQUESTS_CA_BUNDLE:-${SSL_CERT_FILE:-/etc/ssl/certs/ca-certificates.crt}}}
pip_env=()
if [ -f "$host_ca" ]; then
  mkdir -p "$root/etc/ssl/certs"
  cp -L "$host_ca" "$root/etc/ssl/certs/spectralize-host-ca.crt"
  pip_env+=(PIP_CERT=/etc/ssl/certs/spectralize-host-ca.crt)
fi
while IFS='=' read -r name value; do
  case $name in
    PIP_CERT | PIP_FIND_LINKS) ;;  # the bundle above; links to this machine's folders
    PIP_*) pip_env+=("$name=$value") ;;
  esac
done < <(env)
grep -q localhost "$root/etc/hosts" 2>/dev/null || printf '127.0.0.1\tlocalhost\n' >>"$root/etc/hosts"

bind /proc /proc
bind /dev /dev
bind /sys /sys

# The checkout as a clean clone would have it: tracked and untracked files, no build trees. A
# file whose bytes changed gets the time of the copy (the build there rebuilds what depends on
# it, whenever it was edited); unchanged files keep theirs; files gone from the checkout go.
say "copying $src to $root/work/spectralize"
copy="$root/work/spectralize"
incoming="$root/work/.incoming"
rm -rf "$incoming"
mkdir -p "$copy" "$incoming"
(cd "$src" && git ls-files -co --exclude-standard -z | tar --null -T - -cf -) | tar -C "$incoming" -xf -
(cd "$incoming" && find . -type f -print0) | while IFS= read -r -d '' f; do
  if ! cmp -s "$incoming/$f" "$copy/$f"; then
    mkdir -p "$(dirname "$copy/$f")"
    cp "$incoming/$f" "$copy/$f"
  fi
done
(cd "$copy" && find . -path ./build -prune -o -path './build-*' -prune -o -path ./.git -prune \
  -o -type f -print0) | while IFS= read -r -d '' f; do
  [ -e "$incoming/$f" ] || rm -f "$copy/$f"
done
rm -rf "$incoming"
if [ -d "$src/.git" ]; then
  rm -rf "$copy/.git"
  cp -a "$src/.git" "$copy/.git"
fi

in_root() {
  chroot "$root" /usr/bin/env -i HOME=/root PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin \
    LANG=C.UTF-8 TERM=dumb DEBIAN_FRONTEND=noninteractive "${pip_env[@]}" \
    bash -c "cd /work/spectralize && $1" \
    in-root "${@:2}"
}
start=$(date +%s)
status=0
if [ -n "$shell_command" ]; then
  in_root "$shell_command" || status=$?
  say "'$shell_command' in the root: exit $status after $(($(date +%s) - start)) s"
  exit $status
fi
# Each make target installs what it needs (cmake/install-deps.sh); a fresh root lacks make.
in_root 'command -v make >/dev/null || { apt-get update -qq && apt-get install -y -qq make >/dev/null; }
  make "$@" CMAKE_FLAGS=-DSPECTRALIZE_WERROR=ON' "${targets[@]}" || status=$?

versions=$(chroot "$root" dpkg-query -W -f='${Package} ${Version}\n' libopenimageio-dev \
  libopencolorio-dev libopenexr-dev libimath-dev g++ cmake python3 python3-numpy pybind11-dev \
  libgtest-dev libfmt-dev slurmd 2>/dev/null | sed 's/^/  /' || true)
say "stack in the root ($suite):"
echo "$versions"
say "make ${targets[*]} in the root: exit $status after $(($(date +%s) - start)) s"
exit $status
