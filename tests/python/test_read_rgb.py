"""spectralize.read_rgb(): an image's colour as the CLI decides it. Oracles: the CLI's report of
the same file (its colour space and reason), the sRGB curve written out here (IEC 61966-2-1),
and OpenImageIO reading the pixels."""
import json
import os
import subprocess

import numpy as np
import OpenImageIO as oiio
import pytest

from conftest import IMAGES


def cli_decision(path, tmp_path):
    report = tmp_path / "report.json"
    p = subprocess.run([os.environ["SPECTRALIZE_EXE"], str(path), "-o", str(tmp_path / "o.exr"),
                        "--report", str(report), "-q"], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    r = json.loads(report.read_text())
    return r["colorspace"], r["colorspace_reason"]


IDENTITY = ("colorspace_interop_id", "colorspace_interop_id_source", "colorspace_encoding")


def srgb_decode(code):
    v = np.asarray(code, dtype=np.float64) / 255
    return np.where(v <= 0.04045, v / 12.92, np.power((v + 0.055) / 1.055, 2.4))


def test_an_srgb_texture_is_decided_and_decoded_as_the_cli_does(sp, tmp_path):
    path = IMAGES / "colorchecker_srgb8.png"
    rgb, info = sp.read_rgb(str(path))
    assert (info["colorspace"], info["colorspace_reason"]) == cli_decision(path, tmp_path)
    assert info["linear_colorspace"] == "Linear Rec.709 (sRGB)"
    assert info["mode"] == "reflectance"
    # The Color Interop Forum's ID of sRGB-encoded Rec.709, and the shipped config's encoding.
    assert tuple(info[k] for k in IDENTITY) == ("srgb_rec709_scene", "measured", "sdr-video")
    pixels = np.asarray(oiio.ImageInput.open(str(path)).read_image(0, 0, 0, 3, "uint8"))
    assert rgb.shape == pixels.shape and rgb.dtype == np.float32
    # OCIO's float processor: within a few float ulps of the curve.
    assert np.max(np.abs(rgb - srgb_decode(pixels))) <= 2e-6


def test_a_linear_map_is_read_as_it_is(sp, tmp_path):
    path = IMAGES / "hdri_forest_256x128.exr"
    rgb, info = sp.read_rgb(path)  # a PathLike
    assert (info["colorspace"], info["colorspace_reason"]) == cli_decision(path, tmp_path)
    pixels = np.asarray(oiio.ImageInput.open(str(path)).read_image(0, 0, 0, 3, "float"))
    assert np.array_equal(rgb, pixels)


def test_the_given_colour_space_is_followed(sp):
    rgb, info = sp.read_rgb(str(IMAGES / "colorchecker_srgb8.png"), colorspace="Linear Rec.709 (sRGB)")
    assert info["colorspace"] == "Linear Rec.709 (sRGB)"
    assert info["colorspace_reason"].endswith("colorspace")  # the option, as the CLI words it
    pixels = np.asarray(oiio.ImageInput.open(str(IMAGES / "colorchecker_srgb8.png"))
                        .read_image(0, 0, 0, 3, "float"))
    assert np.max(np.abs(rgb - pixels)) <= 1e-7


def test_what_has_no_colour_is_refused_naming_the_file(sp, tmp_path):
    normal = tmp_path / "wall_normal.png"
    normal.write_bytes((IMAGES / "colorchecker_srgb8.png").read_bytes())
    with pytest.raises(ValueError, match="wall_normal.png.*not colour"):
        sp.read_rgb(str(normal))
    with pytest.raises(OSError, match="missing.png"):
        sp.read_rgb(str(tmp_path / "missing.png"))
    with pytest.raises(ValueError, match="No Such Space"):
        sp.read_rgb(str(IMAGES / "colorchecker_srgb8.png"), colorspace="No Such Space")
    with pytest.raises(ValueError, match="compression"):
        sp.read_rgb(str(IMAGES / "colorchecker_srgb8.png"), compression="zip")
