"""Every format this OpenImageIO writes x every sample type, compression and tile size, written
by convert(to='rgb') (the CLI's --to-rgb checks and job): either the file holds exactly what was
asked (OIIO reads it back) or the call is refused before any work, naming the file and the
option. Nothing is quietly something else."""
import os

import numpy as np
import OpenImageIO as oiio
import pytest

TYPES = ["uint8", "uint16", "half", "float"]
# Plausible --compression values (names and levels of several formats).
COMPRESSIONS = ["none", "rle", "zip", "zip:1", "zip:9", "lzw", "packbits", "piz", "dwaa:45",
                "htj2k256", "htj2k32", "jpeg:20", "jpeg:95", "webp:20", "webp:95", "heic:20",
                "jpegxl:20", "jpegxl:100"]
# What must work (the test's own list, not the table's).
MUST_WORK = {("exr", "half"), ("exr", "float"), ("tif", "uint8"), ("tif", "uint16"),
             ("tif", "float"), ("png", "uint8"), ("png", "uint16"), ("jpg", "uint8"),
             ("hdr", "float")}


def writable_extensions():
    """One extension per format this OIIO writes (its own lists)."""
    formats = oiio.get_string_attribute("output_format_list").split(",")
    by_format = {}
    for entry in oiio.get_string_attribute("extension_list").split(";"):
        name, _, exts = entry.partition(":")
        by_format[name] = exts.split(",")
    return {f: by_format[f][0] for f in formats if f in by_format and by_format[f][0]}


EXTENSIONS = writable_extensions()


@pytest.fixture(scope="module")
def spectral(tmp_path_factory):
    """A 64 x 48 emissive spectral EXR with varied colours (compressible, not trivial)."""
    path = tmp_path_factory.mktemp("formats") / "in.exr"
    nm = [400, 450, 500, 550, 600, 650, 700]
    spec = oiio.ImageSpec(64, 48, len(nm), "float")
    spec.channelnames = tuple(f"S0.{n}nm" for n in nm)
    y, x = np.mgrid[0:48, 0:64]
    px = np.stack([0.3 + 0.2 * np.sin(0.2 * x + 0.1 * y + i) for i in range(len(nm))], axis=-1)
    out = oiio.ImageOutput.create(str(path))
    assert out.open(str(path), spec) and out.write_image(px.astype(np.float32)) and out.close()
    return path


# OpenEXR's compression codes, in the order its file format gives them (ImfCompression.h).
EXR_CODES = ["none", "rle", "zips", "zip", "piz", "pxr24", "b44", "b44a", "dwaa", "dwab",
             "htj2k256", "htj2k32"]


def exr_compression(path):
    """The compression an OpenEXR's header records, read from its bytes (OpenImageIO 3.1 does
    not report the HTJ2K ones)."""
    data = open(path, "rb").read(1 << 16)
    assert data[:4] == b"\x76\x2f\x31\x01", path
    at = 8
    while True:
        end = data.index(b"\0", at)
        name = data[at:end]
        if not name:
            return None
        kind_end = data.index(b"\0", end + 1)
        size = int.from_bytes(data[kind_end + 1:kind_end + 5], "little")
        value = data[kind_end + 5:kind_end + 5 + size]
        if name == b"compression":
            return EXR_CODES[value[0]]
        at = kind_end + 5 + size


def read_spec(path):
    inp = oiio.ImageInput.open(str(path))
    assert inp, oiio.geterror()
    spec = inp.spec()
    inp.close()
    return spec


def attempt(sp, src, out, **options):
    """(True, None) when written, (False, message) when refused; refusals leave nothing."""
    try:
        sp.convert(src, out, to="rgb", **options)
        return True, None
    except (ValueError, OSError) as e:
        assert not out.exists(), f"{out.name}: refused but written"
        assert not [p for p in out.parent.iterdir() if ".spectralize-" in p.name]
        # Python's users read keywords (format='uint8'), not the command line's flags.
        assert "--" not in str(e).replace(str(out.parent), ""), str(e)
        return False, str(e)


@pytest.mark.parametrize("fmt", sorted(EXTENSIONS))
def test_every_sample_type(sp, spectral, tmp_path, fmt):
    ext = EXTENSIONS[fmt]
    for t in TYPES:
        out = tmp_path / f"{t}.{ext}"
        ok, why = attempt(sp, spectral, out, format=t)
        if (ext, t) in MUST_WORK:
            assert ok, why
        if ok:
            assert read_spec(out).format == oiio.TypeDesc(t), f"{fmt}: asked {t}"
        else:
            assert out.name in why and ("format" in why or "write ." in why), why


@pytest.mark.parametrize("fmt", sorted(EXTENSIONS))
def test_every_compression(sp, spectral, tmp_path, fmt):
    ext = EXTENSIONS[fmt]
    sizes = {}
    for c in COMPRESSIONS:
        out = tmp_path / f"{c.replace(':', '_')}.{ext}"
        ok, why = attempt(sp, spectral, out, compression=c)
        if ok:
            sizes[c] = os.path.getsize(out)
            # Where the file says its compression (OpenEXR, TIFF), it is the one asked.
            if fmt == "openexr":
                stored = exr_compression(out)
            else:
                stored = read_spec(out).get_string_attribute("compression")
            if fmt in ("openexr", "tiff"):
                assert stored == c.split(":")[0], f"{fmt}: asked {c}, stored {stored}"
        else:
            # A name no format of this build takes is refused as a value, listing the valid
            # ones (htj2k256 before OpenEXR 3.4); any other refusal names the file.
            assert "compression" in why and (out.name in why or "(valid: " in why), why
    # Levels asked are levels used: two levels of one codec give two files.
    for a, b in [("zip:1", "zip:9"), ("jpeg:20", "jpeg:95"), ("webp:20", "webp:95"),
                 ("jpegxl:20", "jpegxl:100")]:
        if a in sizes and b in sizes:
            assert sizes[a] != sizes[b], f"{fmt}: {a} and {b} wrote the same file"
    if ext == "png":
        assert {"zip", "zip:1", "zip:9"} <= set(sizes)


@pytest.mark.parametrize("fmt", sorted(EXTENSIONS))
def test_every_tile_size(sp, spectral, tmp_path, fmt):
    ext = EXTENSIONS[fmt]
    for tile in (32, 40):
        out = tmp_path / f"t{tile}.{ext}"
        ok, why = attempt(sp, spectral, out, tile=tile)
        if ok:
            spec = read_spec(out)
            assert (spec.tile_width, spec.tile_height) == (tile, tile), f"{fmt}: tile {tile}"
        else:
            assert out.name in why and "til" in why, why
    if ext in ("exr", "tif"):
        assert (tmp_path / f"t32.{ext}").exists()
