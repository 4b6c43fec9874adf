"""spectralize.rt: render-time tables from Python at table speed, over the evaluator renderers
link. Truths by the NumPy oracle of conftest.py (never the library's weights): a table made by
table() gives reflectances in [0, 1] that reproduce their colours to 1e-5; colours it cannot
have are counted and get zero spectra; wavelengths of one's own are the piecewise-linear
values; a bad path raises OSError naming it."""
import numpy as np
import pytest

from conftest import relative_error


@pytest.fixture(scope="module")
def srgb_table(sp, tmp_path_factory):
    path = tmp_path_factory.mktemp("rt") / "srgb.spztab"
    sp.table(str(path), colorspace="Linear Rec.709 (sRGB)", mode="reflectance",
             wavelengths="380:780:10")
    return sp.rt.Table(str(path))


def test_a_tables_spectra_reproduce_their_colours_within_bounds(sp, srgb_table, oracle):
    t = srgb_table
    assert t.mode == "reflectance" and t.colorspace == "Linear Rec.709 (sRGB)"
    wl = t.wavelengths
    assert wl.dtype == np.float64 and wl[0] == 380 and wl[-1] == 780 and wl.size == 41
    rng = np.random.default_rng(3)
    rgb = rng.uniform(0.02, 0.95, size=(20, 30, 3)).astype(np.float32)
    values, counts = t.spectra(rgb)
    assert values.shape == (20, 30, 41) and values.dtype == np.float32
    assert counts == {"exact": 600, "mapped": 0, "invalid": 0, "negative": 0}
    assert values.min() >= 0 and values.max() <= 1
    xyz = oracle.reflectance_xyz(values.reshape(-1, 41), wl)
    target = oracle.reflectance_target(rgb.reshape(-1, 3).astype(np.float64), wl)
    assert relative_error(xyz, target) <= 1e-5
    # On two threads and on one: the same numbers.
    assert np.array_equal(t.spectra(rgb, threads=1)[0], t.spectra(rgb, threads=2)[0])
    # Over several chunks of the pool (4096 colours each), inside and outside the gamut: the
    # same spectra and the same counts, every colour counted once.
    many = rng.uniform(-0.2, 1.3, size=(20000, 3)).astype(np.float32)
    one, one_counts = t.spectra(many, threads=1)
    two, two_counts = t.spectra(many, threads=2)
    assert np.array_equal(one, two) and one_counts == two_counts
    assert sum(one_counts.values()) == 20000 and one_counts["mapped"] > 0


def test_colours_it_cannot_have_are_counted_and_get_zero_spectra(srgb_table):
    rgb = np.array([[np.nan, 0.5, 0.5], [np.inf, 0, 0], [-1, -1, -1], [1.5, 0.2, 0.1],
                    [0.3, 0.3, 0.3]], dtype=np.float64)
    values, counts = srgb_table.spectra(rgb)
    assert counts == {"exact": 1, "mapped": 1, "invalid": 2, "negative": 1}
    assert not values[:3].any()
    assert np.all(np.isfinite(values)) and values.max() <= 1


def test_wavelengths_of_ones_own_are_the_piecewise_linear_values(srgb_table):
    rgb = np.array([0.2, 0.6, 0.3])
    bands, _ = srgb_table.spectra(rgb)
    nm = np.array([380, 385.5, 542.25, 779.9, 780, 300, 900], dtype=np.float32)
    values, _ = srgb_table.spectra(rgb, wavelengths=nm)
    want = np.interp(nm, srgb_table.wavelengths, bands, left=0, right=0)
    assert values.shape == (7,)
    assert np.allclose(values, want, atol=1e-6)


def test_blends_are_the_spectra(sp, srgb_table, tmp_path):
    """Oracle: spectra() of the same colours, and the weights' own sums (1 for a reflectance,
    X+Y+Z of the colour for a light, 0 for colours without a spectrum)."""
    rng = np.random.default_rng(5)
    rgb = rng.uniform(-0.1, 1.2, size=(300, 2, 3)).astype(np.float32)
    rgb[0, 0] = np.nan
    for t, scale in ((srgb_table, None), (None, "emission")):
        if t is None:
            path = tmp_path / "light.spztab"
            sp.table(str(path), colorspace="Linear Rec.709 (sRGB)", mode="emission",
                     wavelengths="380:780:10")
            t = sp.rt.Table(str(path))
        rows, weights, samples, counts = t.blend(rgb)
        assert rows.shape == (300, 2, 4) and rows.dtype == np.uint32
        assert weights.shape == (300, 2, 4) and weights.dtype == np.float32
        assert samples.shape[1] == t.wavelengths.size and samples.dtype == np.float32
        assert rows.max() < samples.shape[0]
        values, want_counts = t.spectra(rgb)
        assert counts == want_counts
        blended = np.einsum("...k,...kn->...n", weights, samples[rows])
        if t.mode == "reflectance":
            blended = np.minimum(blended, 1.0)
        assert np.max(np.abs(blended - values)) <= 1e-5 * max(1.0, float(np.abs(values).max()))
        sums = weights.sum(-1)
        assert sums[0, 0] == 0  # NaN: the zero spectrum
        valid = np.isfinite(rgb).all(-1) & (sums != 0)
        if t.mode == "reflectance":
            assert np.allclose(sums[valid], 1.0, atol=1e-5)
        assert np.all(weights >= 0)


def test_a_bad_file_is_refused_naming_it(sp, tmp_path):
    missing = tmp_path / "missing.spztab"
    with pytest.raises(OSError, match="missing.spztab"):
        sp.rt.Table(str(missing))
    not_a_table = tmp_path / "x.spztab"
    not_a_table.write_bytes(b"0" * 2048)
    with pytest.raises(OSError, match="SPZTABLE"):
        sp.rt.Table(str(not_a_table))
    with pytest.raises(OSError, match="x.spztab"):
        sp.rt.Table(str(not_a_table))


def test_the_docstrings_say_the_options(sp):
    doc = sp.rt.Table.spectra.__doc__
    for word in ("rgb", "wavelengths", "threads", "counts", "Cost"):
        assert word in doc


class _OutOfMemory:
    """An array-like whose conversion runs out of memory, as a huge list can."""

    def __array__(self, *args, **kwargs):
        raise MemoryError("no room for the array")


@pytest.mark.parametrize("method", ["spectra", "blend"])
def test_bad_arguments_get_the_modules_and_the_clis_rules(srgb_table, method):
    """The rules of spectralize.spectra() and of the CLI's --threads, each with its own
    message: never parsed as numbers, never truncated, never silently accepted."""
    call = getattr(srgb_table, method)
    where = r"rt\.Table\.%s\(\): " % method
    with pytest.raises(TypeError, match=where + r"rgb: dtype <U3 is not floating point"):
        call(np.array([["0.1", "0.2", "0.3"]]))
    with pytest.raises(TypeError, match=where + r"rgb: dtype complex128 is not floating point"):
        call(np.array([[0.1 + 1j, 0.2, 0.3]]))
    with pytest.raises(TypeError, match=where + r"rgb: dtype int64 is not floating point"):
        call(np.array([[1, 0, 0]], dtype=np.int64))
    with pytest.raises(ValueError, match=where + r"rgb: shape \(2, 4\): the last axis must have 3"):
        call(np.zeros((2, 4)))
    with pytest.raises(MemoryError, match="no room for the array"):
        call(_OutOfMemory())
    for threads in (-1, -100, 10 ** 6, 1025):
        with pytest.raises(ValueError, match=r"rt\.Table\.%s\(\): threads: '%d'" % (method, threads)):
            call(np.full((2, 3), 0.3), threads=threads)
    with pytest.raises(TypeError, match=r"threads: expected a string or a number, got a bool"):
        call(np.full((2, 3), 0.3), threads=True)
    with pytest.raises(ValueError, match=r"threads: '1.5'"):
        call(np.full((2, 3), 0.3), threads=1.5)
    # The bounds themselves are fine; NaN is counted, not refused (a renderer's lookup).
    for threads in (0, 1, 1024):
        assert call(np.array([[0.3, 0.3, 0.3], [np.nan, 0, 0]]), threads=threads)[-1]["invalid"] == 1


def test_bad_wavelengths_are_refused_naming_them(srgb_table):
    rgb = np.full((2, 3), 0.3)
    with pytest.raises(TypeError, match=r"rt\.Table\.spectra\(\): wavelengths: dtype <U3 is not a number"):
        srgb_table.spectra(rgb, wavelengths=np.array(["500"]))
    with pytest.raises(TypeError, match=r"wavelengths: dtype complex128 is not a number"):
        srgb_table.spectra(rgb, wavelengths=np.array([500 + 1j]))
    with pytest.raises(ValueError, match=r"wavelengths: expected a 1-D array"):
        srgb_table.spectra(rgb, wavelengths=np.zeros((2, 2)))
    with pytest.raises(ValueError, match=r"wavelengths: an empty array"):
        srgb_table.spectra(rgb, wavelengths=np.zeros(0))
