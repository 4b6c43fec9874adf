"""Bad arguments: a Python exception naming the argument, never a crash. Includes a small
fuzz of the argument handling (random shapes, dtypes, option names and values)."""
import subprocess
import sys

import os

import numpy as np
import pytest
from conftest import IMAGES


@pytest.mark.parametrize(
    "rgb, error, message",
    [
        (np.zeros((4, 4)), ValueError, r"rgb: shape \(4, 4\): the last axis must have 3 values"),
        (np.zeros((2, 3), dtype=np.int32), TypeError, r"rgb: dtype int32 is not floating point"),
        (np.zeros((2, 3), dtype=np.uint8), TypeError, r"rgb: dtype uint8"),
        (np.zeros((2, 3), dtype=bool), TypeError, r"rgb: dtype bool"),
        (np.zeros((2, 3), dtype=complex), TypeError, r"rgb: dtype complex128"),
        (np.array([[0.1, np.nan, 0.2], [0, 0, np.inf]]), ValueError,
         r"rgb: 2 values are NaN or infinite .* first at \(0, 1\)"),
        (np.array([1e300, 0, 0]), ValueError, r"rgb: 1 value is NaN or infinite \(or beyond float32"),
        (np.float64(0.5), ValueError, r"rgb: a scalar"),
        ("0.1,0.2,0.3", TypeError, r"rgb: dtype <U11"),
        (np.zeros((3, 0)), ValueError, r"the last axis must have 3 values"),
        ([[0.1, 0.2], [0.3]], ValueError, r"."),
    ],
)
def test_bad_rgb(sp, rgb, error, message):
    with pytest.raises(error, match=message):
        sp.spectra(rgb)


@pytest.mark.parametrize(
    "options, error, message",
    [
        ({"mode": "light"}, ValueError, r"spectra\(\): mode: 'light' \(valid: auto, emission, reflectance\)"),
        ({"modes": "emission"}, ValueError, r"spectra\(\): unknown option 'modes' \(valid: colorspace, mode,"),
        ({"colorspace": "Linear sRGB 2"}, ValueError, r"spectra\(\): colorspace: unknown colour space"),
        ({"wavelengths": "380:780:0"}, ValueError, r"spectra\(\): wavelengths"),
        ({"wavelengths": (380, 780, 5)}, TypeError, r"wavelengths: expected a string or a number, got tuple"),
        ({"model": "magic"}, ValueError, r"spectra\(\): model: unknown model 'magic' \(valid: exemplar, natural, smooth, paper\)"),
        ({"illuminant": "D1"}, ValueError, r"spectra\(\): illuminant"),
        ({"threads": -1}, ValueError, r"spectra\(\): threads"),
        ({"threads": True}, TypeError, r"threads: expected a string or a number, got a bool"),
        ({"compression": "zip"}, ValueError, r"unknown option 'compression'"),
        ({"config": "/nonexistent/config.ocio"}, ValueError, r"spectra\(\): config: .*nonexistent"),
    ],
)
def test_bad_options(sp, options, error, message):
    with pytest.raises(error, match=message):
        sp.spectra([0.2, 0.3, 0.4], **options)


def test_none_means_the_default(sp):
    a = sp.spectra([0.2, 0.3, 0.4], mode=None, colorspace=None)[1]
    assert np.array_equal(a, sp.spectra([0.2, 0.3, 0.4])[1])


def test_bad_to_rgb_arguments(sp):
    wl, v = sp.spectra(np.full((2, 3), 0.3))
    with pytest.raises(ValueError, match=r"values: shape \(2, 81\): the last axis must have 80 values"):
        sp.to_rgb(v, wl[:-1])
    with pytest.raises(ValueError, match=r"wavelengths must increase strictly"):
        sp.to_rgb(v, wl[::-1])
    with pytest.raises(ValueError, match=r"wavelengths: expected a 1-D array"):
        sp.to_rgb(v, np.stack([wl, wl]))
    with pytest.raises(ValueError, match=r"no band inside 360-830 nm"):
        sp.to_rgb(v, wl + 1000)
    with pytest.raises(ValueError, match=r"single spectral band"):
        sp.to_rgb(v[:, :1], wl[:1])
    with pytest.raises(ValueError, match=r"view needs display"):
        sp.to_rgb(v, wl, view="Standard")
    with pytest.raises(ValueError, match=r"unknown option 'format'"):
        sp.to_rgb(v, wl, format="uint8")


def test_fuzz_arguments_never_crash(tmp_path):
    """Random arguments in a child interpreter: every call returns or raises a Python
    exception (a crash would kill the child)."""
    script = r"""
import numpy as np, spectralize, warnings
warnings.simplefilter("ignore")
rng = np.random.default_rng(7)
dtypes = [np.float16, np.float32, np.float64, np.int8, np.uint16, np.int64, bool, complex, object]
keys = ["mode", "colorspace", "wavelengths", "model", "filter", "curvature", "emission_basis",
        "illuminant", "observer", "threads", "method", "config", "bogus", "", "mode\0x"]
values = ["", "auto", "reflectance", "emission", "ACEScg", "380:780:5", "1:2:3", "-1", "0",
          "1e308", "nan", "paper", "smooth", "D65", "FL2", "x" * 10000, "\xff", 3, -7, 2.5,
          float("nan"), None, [1, 2], b"bytes"]
n = 0
for i in range(1500):
    shape = tuple(int(s) for s in rng.integers(0, 4, size=rng.integers(0, 4))) + (
        (3,) if rng.random() < 0.7 else (int(rng.integers(0, 6)),))
    dt = dtypes[rng.integers(len(dtypes))]
    try:
        arr = (rng.normal(size=shape) * 10 ** rng.integers(-3, 40)).astype(dt)
    except Exception:
        continue
    if rng.random() < 0.1 and arr.size:
        arr = arr.astype(np.float64); arr.flat[0] = np.nan
    opts = {}
    for _ in range(rng.integers(0, 3)):
        opts[keys[rng.integers(len(keys))]] = values[rng.integers(len(values))]
    try:
        wl, v = spectralize.spectra(arr, **opts)
        back = spectralize.to_rgb(v, wl, mode=opts.get("mode") if opts.get("mode") in ("emission", "reflectance") else None)
        assert back.shape == np.shape(arr)[:-1] + (3,)
        n += 1
    except (ValueError, TypeError):
        pass
print("ok", n)
"""
    p = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr[-3000:]
    assert p.stdout.startswith("ok"), p.stdout
    assert int(p.stdout.split()[1]) > 50  # some calls were valid and ran


# A setting that cannot shape the result is refused by every function as by the command line
# (pipeline/job_plan.h), naming it: the filter on a model without one, the emission basis on
# reflectances, the illuminant on light; left to each input ("auto"), only what shapes neither.
def test_a_setting_that_shapes_nothing_is_refused(sp, tmp_path):
    png = str(IMAGES / "grey_ramp8.png")
    cases = [
        (lambda: sp.spectra([0.2, 0.3, 0.4], model="natural", filter="0.5"),
         r"spectra\(\): filter does not shape emission spectra of the natural model; leave it out"),
        (lambda: sp.spectra([0.2, 0.3, 0.4], mode="reflectance", emission_basis="D65"),
         r"emission_basis does not shape reflectance spectra of the exemplar model"),
        (lambda: sp.spectra([0.2, 0.3, 0.4], illuminant="A"),
         r"illuminant does not shape emission spectra"),
        (lambda: sp.table(str(tmp_path / "t.spztab"), mode="emission", illuminant="A"),
         r"illuminant does not shape an emission table of the exemplar model"),
        (lambda: sp.convert(png, str(tmp_path / "o.exr"), model="smooth", filter="0.5"),
         r"filter does not shape the spectra of the smooth model, a light's or a surface's"),
    ]
    for call, message in cases:
        with pytest.raises(ValueError, match=message):
            call()
    assert not os.listdir(tmp_path), "nothing is written"
    # A surface's illuminant for an image whose mode is decided from the file: it may shape it.
    sp.convert(png, str(tmp_path / "o.exr"), illuminant="A")
    assert os.path.exists(tmp_path / "o.exr")


def test_a_space_no_colour_converts_through_is_refused_by_every_function(sp, tmp_path):
    """A config space whose matrix is zero: every function refuses it before converting,
    naming the space and the reason (as the CLI does with exit 2), and writes nothing."""
    shipped = (IMAGES.parent / "ocio_configs" / "spectralize.ocio").read_text()
    config = tmp_path / "broken.ocio"
    config.write_text(shipped + "\n  - !<ColorSpace>\n    name: Zero\n    isdata: false\n"
                      "    to_scene_reference: !<MatrixTransform> {matrix: "
                      "[0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1]}\n")
    opts = {"config": str(config), "colorspace": "Zero"}
    refused = r"colorspace: colour space 'Zero' .* cannot be used: its conversion to CIE XYZ makes every colour black"
    wl, values = sp.spectra(np.full((2, 3), 0.3))
    src = str(IMAGES / "colorchecker_srgb8.png")
    calls = {
        "spectra": lambda: sp.spectra([0.2, 0.3, 0.4], **opts),
        "to_rgb": lambda: sp.to_rgb(values, wl, **opts),
        "convert": lambda: sp.convert(src, str(tmp_path / "a.exr"), **opts),
        "ingest": lambda: sp.ingest([src], str(tmp_path / "dst"), **opts),
        "table": lambda: sp.table(str(tmp_path / "t.spztab"), **opts),
        "read_rgb": lambda: sp.read_rgb(src, **opts),
    }
    for name, call in calls.items():
        with pytest.raises(ValueError, match=refused):
            call()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["broken.ocio"]
