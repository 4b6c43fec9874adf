"""What holds for Python buffers and options: an `out` that shares memory with `rgb` gives the
same numbers as a separate one, NumPy scalars are options like Python numbers, float64
wavelengths are used as given, and every option of a call is honoured whatever the calls
before it (including a changed $OCIO or config file)."""
import os
import pathlib

import numpy as np
import pytest

from conftest import SOURCE

RNG = np.random.default_rng(2026)


def colours(n):
    return RNG.uniform(0.05, 0.9, size=(n, 3)).astype(np.float32)


@pytest.mark.parametrize("layout", ["same start", "inside", "reversed view", "strided"])
def test_out_sharing_memory_with_rgb_gives_the_same_numbers(sp, layout):
    """Reproduction: 198,976 of 200,000 rows were wrong when `out` overlapped `rgb`. Oracle: the
    same call with a separate output array."""
    n = 200_000
    rgb = colours(n)
    wl, expected = sp.spectra(rgb)
    bands = wl.size
    buf = np.zeros(n * bands, dtype=np.float32)
    if layout == "same start":  # rgb is the first n*3 values of out
        view = buf[: n * 3].reshape(n, 3)
        view[...] = rgb
    elif layout == "inside":  # rgb starts inside out, not at its start
        view = buf[1000: 1000 + n * 3].reshape(n, 3)
        view[...] = rgb
    elif layout == "reversed view":  # negative strides: copied by the reader, still overlapping
        view = buf[: n * 3].reshape(n, 3)[::-1]
        view[...] = rgb
    else:  # a strided view into out
        view = buf.reshape(n, bands)[:, 10:13]
        view[...] = rgb
    given = view.copy()
    out = buf.reshape(n, bands)
    _, got = sp.spectra(view, out=out)
    assert got is out
    wl2, again = sp.spectra(given)
    assert np.array_equal(got, again)
    if layout != "reversed view":
        assert np.array_equal(got, expected)


def test_numpy_scalars_are_options_like_python_numbers(sp):
    rgb = colours(50)
    base = sp.spectra(rgb, threads=2, mode="reflectance", model="paper", filter=0.7)[1]
    for threads in (np.int64(2), np.int32(2), np.uint8(2)):
        got = sp.spectra(rgb, threads=threads, mode="reflectance", model="paper", filter=0.7)[1]
        assert np.array_equal(got, base)
    for f in (np.float64(0.7), np.float32(0.7), np.float16(0.7)):
        got = sp.spectra(rgb, mode="reflectance", model="paper", filter=f)[1]
        assert np.array_equal(got, base), type(f)
    with pytest.raises(TypeError, match=r"threads: expected a string or a number, got a bool"):
        sp.spectra(rgb, threads=np.True_)
    with pytest.raises(ValueError, match=r"threads"):
        sp.spectra(rgb, threads=np.int64(-1))


def test_float64_wavelengths_are_used_as_given(sp, oracle):
    """Reproduction: [500, 500.00001] was refused as not strictly increasing (cut to float32)."""
    wl = np.array([500.0, 500.00001])
    rgb = sp.to_rgb(np.ones((1, 2), dtype=np.float32), wl)
    assert np.all(np.isfinite(rgb))
    # Integer wavelengths (numpy.arange) are wavelengths too; the same result as float ones.
    wl5, v = sp.spectra(colours(20))
    assert np.array_equal(sp.to_rgb(v, np.arange(380, 781, 5)), sp.to_rgb(v, wl5))
    # Sub-float32 spacing changes the integral as the oracle says it should.
    grid = np.array([400.0, 550.0, 550.0001, 700.0])
    values = np.array([[0.0, 0.0, 1.0, 1.0]], dtype=np.float32)
    xyz_rgb = sp.to_rgb(values, grid, colorspace="CIE-XYZ-D65")
    target = oracle.emission_xyz(values, grid)
    assert np.max(np.abs(xyz_rgb - target)) <= 1e-5 * np.max(np.abs(target))


def test_every_option_is_honoured_whatever_came_before(sp):
    """Reproduction: after spectra(mode='reflectance'), illuminant='A' returned the D65
    spectra (the setup cache missed the illuminant). Oracle: each call's result in a fresh
    order equals the one after every other call."""
    rgb = colours(30)
    calls = [
        dict(mode="reflectance"),
        dict(mode="reflectance", illuminant="A"),
        dict(mode="reflectance", illuminant="F2", observer="cie1964"),
        dict(mode="emission", emission_basis="D65"),
        dict(mode="emission", emission_basis="A"),
        dict(mode="reflectance", model="paper", filter=0.3),
        dict(mode="reflectance", model="paper", filter=0.9),
        dict(mode="reflectance", model="smooth", curvature=0.5),
        dict(wavelengths="400:700:10"),
        dict(method="exact"),
        dict(colorspace="ACEScg"),
    ]
    first = [sp.spectra(rgb, **c)[1] for c in calls]
    again = [sp.spectra(rgb, **c)[1] for c in reversed(calls)][::-1]
    for c, a, b in zip(calls, first, again):
        assert np.array_equal(a, b), c
    # Calls that must differ do.
    assert not np.array_equal(first[0], first[1]) and not np.array_equal(first[1], first[2])
    assert not np.array_equal(first[3], first[4]) and not np.array_equal(first[5], first[6])


def test_a_changed_ocio_environment_or_config_file_is_seen(sp, tmp_path, monkeypatch):
    """$OCIO read at each call, and the config file's identity (an edit in place is seen)."""
    rgb = colours(10)
    shipped = (SOURCE / "ocio_configs" / "spectralize.ocio").read_text()
    linear_709 = "scene_linear: Linear Rec.709 (sRGB)"
    assert linear_709 in shipped
    default = sp.spectra(rgb)[1]
    config = tmp_path / "config.ocio"
    config.write_text(shipped.replace(linear_709, "scene_linear: ACEScg"))
    monkeypatch.setenv("OCIO", str(config))
    acescg = sp.spectra(rgb)[1]
    assert np.array_equal(acescg, sp.spectra(rgb, colorspace="ACEScg")[1])
    assert not np.array_equal(acescg, default)
    # The same file, edited in place.
    config.write_text(shipped.replace(linear_709, "scene_linear: Linear Rec.2020"))
    rec2020 = sp.spectra(rgb)[1]
    assert np.array_equal(rec2020, sp.spectra(rgb, colorspace="Linear Rec.2020")[1])
    monkeypatch.delenv("OCIO")
    assert np.array_equal(sp.spectra(rgb)[1], default)
