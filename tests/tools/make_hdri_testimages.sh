#!/usr/bin/env bash
# Regenerates the HDRI test images in testimages/ from Blender's CC0 studio-light
# world maps, as shipped in Debian 12's "blender-data" package (3.4.1+dfsg-2).
#
# Documentation of how the committed files were made; not run by CI.
# Needs: apt-get (network access to the Debian archive), dpkg-deb, oiiotool (OIIO 2.4).
#
# The package is only downloaded and unpacked into a temporary directory; it is
# NOT installed system-wide (it is ~31 MB download / ~100 MB installed).
set -euo pipefail

REPO_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
OUT="${REPO_ROOT}/testimages"
WORK="${WORK:-$(mktemp -d /tmp/blender-data.XXXXXX)}"
mkdir -p "${OUT}"

cd "${WORK}"
if ! ls blender-data_*.deb >/dev/null 2>&1; then
    apt-get download blender-data   # run 'apt-get update' first if this fails
fi
dpkg-deb -x blender-data_*.deb "${WORK}/root"
SRC="${WORK}/root/usr/share/blender/datafiles/studiolights/world"
cat "${SRC}/license.txt"
cd "${SRC}"

# All Blender world maps are 1024x512 float RGB EXR (DWAB-compressed, i.e. lossy),
# scene-linear Rec.709 (no chromaticities attribute in the three used here; OIIO
# reports oiio:ColorSpace "Linear" for them, as it does for any EXR).
# The inherited attribute openexr:dwaCompressionLevel is erased (the copies are
# ZIP/PIZ, so it would only mislead).
ERASE=(--eraseattrib "openexr:dwaCompressionLevel")

# 1) Benchmark map: interior.exr at its native 1024x512, stored as half, PIZ
#    (ZIP would be 1.61 MB, PIZ is 1.44 MB). No resampling.
oiiotool interior.exr "${ERASE[@]}" -d half --compression piz \
    -o "${OUT}/hdri_interior_1024x512.exr"

# 2) Small maps: 4x box-filter downscale to 256x128 (a box filter adds no
#    ringing / new negative lobes around the very bright light sources).
oiiotool sunset.exr --resize:filter=box 256x128 "${ERASE[@]}" -d half --compression zip \
    -o "${OUT}/hdri_sunset_256x128.exr"
oiiotool forest.exr --resize:filter=box 256x128 "${ERASE[@]}" -d half --compression zip \
    -o "${OUT}/hdri_forest_256x128.exr"

# 3) Same sunset map as Radiance RGBE .hdr (from the float source, same filter).
oiiotool sunset.exr --resize:filter=box 256x128 "${ERASE[@]}" \
    -o "${OUT}/hdri_sunset_256x128.hdr"

for f in hdri_interior_1024x512.exr hdri_sunset_256x128.exr hdri_forest_256x128.exr hdri_sunset_256x128.hdr; do
    oiiotool --stats "${OUT}/${f}"
done
