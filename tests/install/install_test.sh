#!/usr/bin/env bash
# cmake --install into a temporary prefix, then use only what was installed: the tool, the
# OIIO plugin with stock oiiotool, the Python module, and the CMake package from a separate
# project. The prefix is moved after installing (nothing may depend on where it was put), no
# installed file may name the build or source tree, and where a private mount namespace is
# available (root, or user namespaces) both trees are hidden under empty tmpfs mounts while the
# installed files run.
# Usage: install_test.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build="$(realpath "$1")"
source="$(realpath "$2")"
work="$(mktemp -d /tmp/spectralize-install.XXXXXX)"
trap 'rm -rf "$work"' EXIT
fail() { echo "FAILED: $*" >&2; exit 1; }

cmake --install "$build" --prefix "$work/staged" >"$work/install.log"
mv "$work/staged" "$work/prefix"
prefix="$work/prefix"
py_version="$(/usr/bin/python3 -c 'import sys; print("%d.%d" % sys.version_info[:2])')"

# The documented layout (the guide's "Install" (docs/guide/install.md)).
for f in bin/spectralize lib/spectralize/plugins/spectral.imageio.so \
         share/spectralize/ocio/spectralize.ocio share/spectralize/data/cie1931_2deg_cmf_1nm.csv \
         share/spectralize/farm/spectralize-ingest.sbatch include/spectralize/version.h \
         include/spectralize/core/spectralizer.h lib/libspectralize_core.a \
         include/spectralize/rt.h include/spectralize/rt.hpp include/spectralize/rt_impl.hpp \
         include/spectralize/rt_format.h \
         lib/libspectralize_rt.a lib/libspectralize_rt.so lib/pkgconfig/spectralize-rt.pc \
         lib/cmake/spectralize/spectralizeConfig.cmake \
         lib/cmake/spectralize/spectralizeConfigVersion.cmake \
         share/doc/spectralize/spectralize-help.txt share/man/man1/spectralize.1 \
         "lib/python$py_version/dist-packages/spectralize.cpython-${py_version/./}-x86_64-linux-gnu.so"; do
  [ -f "$prefix/$f" ] || fail "not installed: $f"
done
grep -q -- "--wavelengths" "$prefix/share/doc/spectralize/spectralize-help.txt" ||
  fail "the installed help text does not list the flags"
# The man page (made by every build) and the HTML guide (when built: make docs, make install).
MANWIDTH=120 man -l "$prefix/share/man/man1/spectralize.1" 2>/dev/null | grep -q -- "--rgb-to-xyz" ||
  fail "the installed man page does not render with its flags"
if [ -f "$build/docs/html/index.html" ]; then
  [ -f "$prefix/share/doc/spectralize/html/index.html" ] &&
    [ -f "$prefix/share/doc/spectralize/html/guide/flags.html" ] ||
    fail "the built guide is not installed under share/doc/spectralize/html"
fi
# The C library: its SONAME is the table format's version; it needs nothing but libc and libm
# and exports nothing but the C API.
so_name="$(readelf -d "$prefix/lib/libspectralize_rt.so" | sed -n 's/.*Library soname: \[\(.*\)\]/\1/p')"
[ "$so_name" = "libspectralize_rt.so.$(sed -n 's/#define SPZ_FORMAT_VERSION \([0-9]*\)u/\1/p' \
  "$prefix/include/spectralize/rt_format.h")" ] || fail "libspectralize_rt's SONAME is '$so_name'"
needed="$(readelf -d "$prefix/lib/libspectralize_rt.so" | sed -n 's/.*Shared library: \[\(.*\)\]/\1/p' |
  grep -v -x -e 'libc.so.6' -e 'libm.so.6' || true)"
[ -z "$needed" ] || fail "libspectralize_rt.so needs more than libc and libm: $needed"
exported="$(nm -D --defined-only "$prefix/lib/libspectralize_rt.so" | awk '{print $3}' | grep -v '^spz_' |
  grep -v -e '^SPECTRALIZE_RT_' || true)"
[ -z "$exported" ] || fail "libspectralize_rt.so exports more than spz_: $exported"
for symbol in spz_table_load spz_fetch spz_eval4 spz_fetch_array spz_samples_n spz_spectrum_max; do
  nm -D --defined-only "$prefix/lib/libspectralize_rt.so" | grep -q " $symbol@" ||
    fail "libspectralize_rt.so does not export $symbol"
done
if nm "$prefix/lib/libspectralize_rt.a" | grep -q -e ' U _Z' -e ' U __cxa' -e ' U __gxx'; then
  fail "libspectralize_rt.a needs the C++ runtime"
fi
echo "libspectralize_rt: $so_name, needs only libc and libm, exports only spz_*"

if hits="$(grep -rl --binary-files=text -e "$build" -e "$source" "$prefix")"; then
  fail "installed files name the build or source tree: $hits"
fi

# What the checks need, copied out of the trees before they are hidden.
cp "$source/testimages/hdri_forest_256x128.exr" "$work/in.exr"
cp -r "$source/tests/install/consumer" "$work/consumer"
cp -r "$source/tests/install/rt_consumer" "$work/rt_consumer"
cp -r "$source/tests/install/rt_c_consumer" "$work/rt_c_consumer"
printf '{"source": "in.exr", "wavelengths": "400:700:10"}\n' >"$work/r.spectral"
# A USD stage written here by hand (a DomeLight and its HDRI), read through OpenUSD where the
# pinned packages' environment has it: the installed tool finds the installed module.
usd_python="${SPECTRALIZE_VENV:-$HOME/.cache/spectralize/venv}/bin/python"
printf '#usda 1.0\ndef DomeLight "Sky"\n{\n    asset inputs:texture:file = @in.exr@\n}\n' \
  >"$work/stage.usda"

cat >"$work/checks.sh" <<CHECKS
set -euo pipefail
cd "$work"
for d in "$source" "$build"; do
  if [ -n "\${HIDDEN:-}" ] && [ -e "\$d" ] && [ -n "\$(ls -A "\$d")" ]; then
    echo "FAILED: \$d is not hidden"; exit 1
  fi
done
unset OCIO OIIO_LIBRARY_PATH PYTHONPATH
PATH="$prefix/bin:/usr/bin:/bin"
spectralize --version
spectralize in.exr -o out.exr -q
oiiotool --info -v out.exr | grep -q "channel list: R, G, B, S0.380,000000nm" ||
  { echo "FAILED: the installed tool's output"; exit 1; }
spectralize --color 0.2,0.5,0.1 --format json --method exact | /usr/bin/python3 -c \
  'import json, sys; e = json.load(sys.stdin)["relative_error"]; assert e <= 1e-12, e; print("color ok", e)'
spectralize --color 0.2,0.5,0.1 --format json | /usr/bin/python3 -c \
  'import json, sys; e = json.load(sys.stdin)["relative_error"]; assert e <= 1e-6, e; print("color (table) ok", e)'
OIIO_LIBRARY_PATH="$prefix/lib/spectralize/plugins" oiiotool r.spectral -o plugin.exr
oiiotool --info plugin.exr | grep -q "256 x  128, 34 channel" ||
  { echo "FAILED: the plugin's image (R, G, B + 31 bands)"; oiiotool --info plugin.exr; exit 1; }
PYTHONPATH="$prefix/lib/python$py_version/dist-packages" /usr/bin/python3 -c '
import spectralize
assert spectralize.__file__.startswith("$prefix/"), spectralize.__file__
wl, v = spectralize.spectra([0.2, 0.5, 0.1], mode="reflectance")
assert wl.size == 81 and 0 <= v.min() and v.max() <= 1
print("python ok", spectralize.__version__, spectralize.__file__)'
cmake -S consumer -B consumer-build -DCMAKE_PREFIX_PATH="$prefix" >/dev/null
cmake --build consumer-build >/dev/null
consumer-build/consumer "$prefix/share/spectralize/data/cie1931_2deg_cmf_1nm.csv"
# A renderer's view: a table made by the installed tool, read by spectralize::rt alone.
spectralize table -o srgb.spztab -q
cmake -S rt_consumer -B rt-consumer-build -DCMAKE_PREFIX_PATH="$prefix" >/dev/null
cmake --build rt-consumer-build >/dev/null
rt_consumer_links="\$(ldd rt-consumer-build/rt_consumer | grep -c spectralize || true)"
[ "\$rt_consumer_links" = 0 ] || { echo "FAILED: rt_consumer links a spectralize library"; exit 1; }
rt-consumer-build/rt_consumer srgb.spztab "$prefix/share/spectralize/data/cie1931_2deg_cmf_1nm.csv" \
  "$prefix/share/spectralize/data/cie_illuminant_d65_1nm.csv"
# A C renderer (a C compiler only) against the C library: by CMake, shared and static; by
# pkg-config; and Python's ctypes loading the shared library.
data="$prefix/share/spectralize/data"
for kind in OFF ON; do
  cmake -S rt_c_consumer -B "rt-c-\$kind" -DSTATIC=\$kind -DCMAKE_PREFIX_PATH="$prefix" >/dev/null
  cmake --build "rt-c-\$kind" >/dev/null
  LD_LIBRARY_PATH="$prefix/lib" "rt-c-\$kind/rt_c_consumer" srgb.spztab \
    "\$data/cie1931_2deg_cmf_1nm.csv" "\$data/cie_illuminant_d65_1nm.csv"
  links="\$(LD_LIBRARY_PATH="$prefix/lib" ldd "rt-c-\$kind/rt_c_consumer" | grep -c libspectralize_rt.so || true)"
  [ "\$links" = "\$([ \$kind = OFF ] && echo 1 || echo 0)" ] ||
    { echo "FAILED: the \$kind consumer links libspectralize_rt.so \$links times"; exit 1; }
done
export PKG_CONFIG_PATH="$prefix/lib/pkgconfig"
cc -std=c99 rt_c_consumer/main.c -o rt-c-pc \$(pkg-config --cflags --libs spectralize-rt)
LD_LIBRARY_PATH="$prefix/lib" ./rt-c-pc srgb.spztab "\$data/cie1931_2deg_cmf_1nm.csv" \
  "\$data/cie_illuminant_d65_1nm.csv"
cc -std=c99 rt_c_consumer/main.c -o rt-c-pc-static \
  \$(pkg-config --cflags spectralize-rt) "$prefix/lib/libspectralize_rt.a" \$(pkg-config --libs-only-l --static spectralize-rt | sed 's/-lspectralize_rt//')
./rt-c-pc-static srgb.spztab "\$data/cie1931_2deg_cmf_1nm.csv" "\$data/cie_illuminant_d65_1nm.csv"
/usr/bin/python3 rt_c_consumer/rt_ctypes.py "$prefix/lib/libspectralize_rt.so" srgb.spztab
if [ -x "$usd_python" ] && "$usd_python" -c "import pxr" 2>/dev/null; then
  SPECTRALIZE_PYTHON="$usd_python" spectralize ingest stage.usda -o usd-out -q --wavelengths 400:700:10
  [ -f usd-out/in.exr ] && grep -q 'spectralize:file = @in.exr@' usd-out/spectral.usda ||
    { echo "FAILED: the installed tool's USD stage"; ls -R usd-out; exit 1; }
  echo "usd stage ok"
else
  echo "no OpenUSD in $usd_python: the USD stage check is skipped"
fi
echo "all installed checks passed"
CHECKS

# Hide the trees where a private mount namespace can be had; else run as is (said so).
hide=""
for d in "$build" "$source"; do hide+="mount -t tmpfs none '$d'; "; done
if unshare -m --propagation private true 2>/dev/null; then
  unshare -m --propagation private bash -c "$hide HIDDEN=1 bash '$work/checks.sh'"
  echo "(build and source trees hidden under tmpfs while the installed files ran)"
else
  echo "NOTE: no private mount namespace here: the trees stayed visible (the relocation and the"
  echo "      no-build-path checks above still apply)"
  bash "$work/checks.sh"
fi
