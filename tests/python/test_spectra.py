"""spectralize.spectra() and to_rgb(): exact, bounded, any shape, the same spectra as the CLI."""
import json
import subprocess
import os
import threading

import numpy as np
import pytest

from conftest import relative_error

RNG = np.random.default_rng(20261129)


def in_gamut_rgb(n):
    """Linear Rec.709 colours inside the reflectance solid: 0.02..0.95."""
    return RNG.uniform(0.02, 0.95, size=(n, 3))


def test_emission_reproduces_colour_by_independent_integration(sp, oracle):
    rgb = RNG.uniform(0.0, 4.0, size=(3000, 3))
    wl, values = sp.spectra(rgb)
    assert wl.dtype == np.float64 and values.dtype == np.float32
    assert np.array_equal(wl, np.arange(380, 781, 5))
    assert values.shape == (3000, 81)
    assert values.min() >= 0
    # Float output: relative XYZ <= 1e-5 (docs/DESIGN.md §3).
    assert relative_error(oracle.emission_xyz(values, wl), oracle.xyz_of_rgb(rgb)) <= 1e-5


def test_reflectance_is_exact_and_within_zero_one(sp, oracle):
    rgb = in_gamut_rgb(3000)
    wl, values = sp.spectra(rgb, mode="reflectance")
    assert values.min() >= 0 and values.max() <= 1
    err = relative_error(oracle.reflectance_xyz(values, wl), oracle.reflectance_target(rgb, wl))
    assert err <= 1e-5


def rgb_to_xyz_matrix(primaries, white=(0.3127, 0.3290)):
    xy = np.array(primaries)
    prim = np.stack([xy[:, 0] / xy[:, 1], np.ones(3), (1 - xy.sum(1)) / xy[:, 1]])
    w = np.array([white[0] / white[1], 1.0, (1 - white[0] - white[1]) / white[1]])
    return prim * np.linalg.solve(prim, w)


def srgb_decode(v):
    return np.where(v <= 0.04045, v / 12.92, ((v + 0.055) / 1.055) ** 2.4)


@pytest.mark.parametrize("space", ["Linear Rec.2020", "sRGB - Texture", "lin_p3d65"])
def test_other_colour_spaces_by_their_standard_definitions(sp, oracle, space):
    """Colours of D65 spaces, converted by the standards' own formulas (not OCIO)."""
    rgb = in_gamut_rgb(500)
    if space == "Linear Rec.2020":
        xyz = rgb @ rgb_to_xyz_matrix([(0.708, 0.292), (0.170, 0.797), (0.131, 0.046)]).T
    elif space == "lin_p3d65":
        xyz = rgb @ rgb_to_xyz_matrix([(0.680, 0.320), (0.265, 0.690), (0.150, 0.060)]).T
    else:
        xyz = oracle.xyz_of_rgb(srgb_decode(rgb))
    wl, v = sp.spectra(rgb, colorspace=space)
    assert relative_error(oracle.emission_xyz(v, wl), xyz) <= 2e-5


def test_any_shape_and_strides(sp):
    rgb = RNG.uniform(0.0, 1.0, size=(4, 5, 6, 3))
    wl, v = sp.spectra(rgb)
    assert v.shape == (4, 5, 6, wl.size)
    flat = sp.spectra(rgb.reshape(-1, 3))[1]
    assert np.array_equal(v.reshape(-1, wl.size), flat)
    # Non-contiguous views (reversed channels, every other row) equal their contiguous copies.
    view = rgb[:, ::2, :, ::-1]
    assert np.array_equal(sp.spectra(view)[1], sp.spectra(np.ascontiguousarray(view))[1])
    # One colour as a plain list; float16 and float32 input.
    assert sp.spectra([0.2, 0.5, 0.1])[1].shape == (wl.size,)
    assert sp.spectra(rgb.astype(np.float16))[1].shape == v.shape
    assert sp.spectra(np.zeros((0, 3)))[1].shape == (0, wl.size)


def test_same_spectra_as_the_cli(sp, tmp_path):
    """spectra() and `spectralize --color` give the same spectra: the same exact table (to the
    float rounding of their colour conversions), or, with method='exact', the same solves."""
    exe = os.environ["SPECTRALIZE_EXE"]
    colours = [(0.2, 0.5, 0.1), (0.8, 0.3, 0.05), (3.0, 2.0, 1.0)]
    for method in ("table", "exact"):
        for c in colours:
            out = subprocess.run([exe, "--color", ",".join(map(str, c)), "--format", "json",
                                  "--wavelengths", "400:700:10", "--method", method],
                                 capture_output=True, text=True, check=True).stdout
            cli = np.array(json.loads(out)["values"])
            wl, v = sp.spectra(np.array(c), wavelengths="400:700:10", method=method)
            assert np.allclose(v, cli, rtol=1e-5, atol=1e-6 * cli.max()), method


def test_options_change_the_grid_and_models(sp, oracle):
    rgb = in_gamut_rgb(50)
    for grid in ["400:700:10", "360:830:1", "380:780:2.5"]:
        wl, v = sp.spectra(rgb, wavelengths=grid, mode="reflectance")
        start, end, step = map(float, grid.split(":"))
        assert wl[0] == start and wl[-1] == end and np.allclose(np.diff(wl), step)
        assert relative_error(oracle.reflectance_xyz(v, wl), oracle.reflectance_target(rgb, wl)) <= 1e-5
    models = [m["name"] for m in sp.models()]
    assert "paper" in models and "smooth" in models
    spectra = [sp.spectra(rgb, mode="reflectance", model=m)[1] for m in models]
    assert not np.allclose(spectra[0], spectra[1])  # different models, different metamers


def test_to_rgb_of_an_independent_spectrum_on_an_uneven_grid(sp, oracle):
    wl = np.array([360, 371, 390, 420, 455, 480, 500, 530, 555, 600, 640, 700, 760, 830.0])
    values = np.stack([np.exp(-0.5 * ((wl - mu) / 40) ** 2) for mu in (450, 550, 620)])
    rgb = sp.to_rgb(values, wl)
    expected = np.linalg.solve(oracle.rgb_to_xyz, oracle.emission_xyz(values, wl).T).T
    assert np.abs(rgb - expected).max() <= 1e-5 * np.abs(expected).max()


def test_round_trip_both_modes(sp):
    rgb = in_gamut_rgb(2000)
    for mode in ("emission", "reflectance"):
        wl, v = sp.spectra(rgb, mode=mode)
        assert np.abs(sp.to_rgb(v, wl, mode=mode) - rgb).max() <= 1e-5


def test_reflectance_as_lit_under_illuminant_a_is_warmer(sp):
    wl, v = sp.spectra(np.array([1.0, 1.0, 1.0]), mode="reflectance")
    assert np.allclose(v, 1.0)  # white is rho = 1 (docs/DESIGN.md §3)
    balanced = sp.to_rgb(v, wl, mode="reflectance", illuminant="A")
    lit = sp.to_rgb(v, wl, mode="reflectance", illuminant="A", reflected="as-lit")
    assert np.allclose(balanced, 1.0, atol=1e-5)  # white stays white, white balanced
    assert lit[0] > lit[1] > lit[2]  # incandescent light is red-heavy


def test_out_of_gamut_colours_are_mapped_and_reported(sp):
    rgb = np.array([[1.0, -1.0, 0.0], [5.0, 5.0, 5.0], [0.2, 0.2, 0.2]])
    with pytest.warns(sp.SpectralizeWarning, match=r"2 colours out of gamut and mapped"):
        wl, v = sp.spectra(rgb, mode="reflectance")
    assert v.min() >= 0 and v.max() <= 1


def test_a_data_colour_space_is_taken_as_xyz_with_a_warning_on_every_call(sp, oracle):
    """As for an image and a --color: the values of a space the config marks as data ('Raw')
    are CIE XYZ, converted exactly, and the warning is said on each call (the setup is kept)."""
    xyz = np.array([[0.2, 0.3, 0.4], [1.5, 1.2, 0.3]])
    for _ in range(2):
        with pytest.warns(sp.SpectralizeWarning,
                          match=r"spectra\(\): colour space 'Raw' is marked as data .* CIE XYZ"):
            wl, values = sp.spectra(xyz, colorspace="Raw")
        assert relative_error(oracle.emission_xyz(values, wl), xyz) <= 1e-5


def test_gil_is_released(sp):
    """Another Python thread keeps running while spectra() works: a watcher thread, started
    before the call (a handshake, not a sleep), notes how many rows of `out` are written each
    time it looks. With the GIL held it could look only before the call (none) and after it
    (all); seeing rows part-written proves it ran during the call (a state, not a time: a slow
    machine slows the call and the watcher alike). About a second of direct solves on one
    thread, written a piece (~0.1 s of work) at a time."""
    rgb = RNG.uniform(0.05, 0.9, size=(20_000, 3))
    out = np.zeros((len(rgb), 81), np.float32)
    sp.spectra(rgb[:100], mode="reflectance", method="exact")  # setup before
    started, stop = threading.Event(), threading.Event()
    seen = set()

    def watcher():
        started.set()
        while not stop.is_set():
            seen.add(int(np.count_nonzero(out[:, 40])))

    t = threading.Thread(target=watcher)
    t.start()
    started.wait()
    sp.spectra(rgb, out=out, mode="reflectance", method="exact", threads=1)
    stop.set()
    t.join()
    part_written = sorted(n for n in seen if 0 < n < len(rgb))
    assert len(part_written) >= 2, sorted(seen)


def test_persistent_cache_is_shared_with_the_cli(sp, tmp_path):
    cache = tmp_path / "cache"
    rgb = RNG.uniform(0, 1, size=(2000, 3))
    wl, v = sp.spectra(rgb, cache=str(cache), wavelengths="400:700:20")
    files = list(cache.glob("spectralize-table-*.bin"))
    assert len(files) == 1 and files[0].stat().st_size > 0
    # The CLI converting an image with the same settings uses the same file.
    exe = os.environ["SPECTRALIZE_EXE"]
    out = tmp_path / "o.exr"
    subprocess.run([exe, os.path.join(os.environ["SPECTRALIZE_SOURCE"], "testimages",
                                      "hdri_forest_256x128.exr"), "-o", str(out), "--cache",
                    str(cache), "--wavelengths", "400:700:20", "-q"], check=True)
    assert list(cache.glob("spectralize-table-*.bin")) == files


def test_out_fills_the_given_array(sp):
    rgb = RNG.uniform(0, 1, size=(10, 3))
    wl, expected = sp.spectra(rgb)
    out = np.full((10, wl.size), -1.0, dtype=np.float32)
    wl2, got = sp.spectra(rgb, out=out)
    assert got is out and np.array_equal(out, expected)
    with pytest.raises(ValueError, match=r"out: shape \(10, 80\), expected \(10, 81\)"):
        sp.spectra(rgb, out=np.empty((10, 80), dtype=np.float32))
    with pytest.raises(TypeError, match=r"out: expected a float32"):
        sp.spectra(rgb, out=np.empty((10, 81)))
    with pytest.raises(ValueError, match=r"out: must be C-contiguous"):
        sp.spectra(rgb, out=np.empty((81, 10), dtype=np.float32).T)


def test_concurrent_calls_with_a_cache_agree_with_serial_ones(sp, tmp_path):
    """Python threads calling spectra() at once (the GIL released), one saving the cache while
    others look up: the same spectra as one call at a time."""
    batches = [RNG.uniform(0, 1, size=(20_000, 3)) for _ in range(6)]
    serial = [sp.spectra(b, mode="reflectance", wavelengths="400:700:10")[1] for b in batches]
    results = [None] * len(batches)

    def work(i):
        results[i] = sp.spectra(batches[i], mode="reflectance", wavelengths="400:700:10",
                                cache=str(tmp_path / "c"))[1]

    threads = [threading.Thread(target=work, args=(i,)) for i in range(len(batches))]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for a, b in zip(results, serial):
        assert np.abs(a - b).max() <= 1e-6
