"""spectralize.usd.lights(): UsdLux lights as emission spectra. Oracles written here from the
project's CSV tables (NumPy, 1 nm, never the library's weights): the reference integration of
docs/DESIGN.md §3 (the trapezoid rule over 360-830 nm of the piecewise-linear spectrum, Y
relative to the integral of ybar), the spaces' matrices from their published primaries and
whites, the CIE D65 table and the D-series from the CIE S0, S1, S2 basis; the white balance
of docs/DESIGN.md §3 (XYZ scaling from the space's white to the basis's)."""
import pathlib

import numpy as np
import pytest

pytest.importorskip("pxr")
from pxr import Gf, Usd, UsdLux  # noqa: E402

DATA = pathlib.Path(__file__).resolve().parents[2] / "data"


def table(name):
    t = np.loadtxt(DATA / name, delimiter=",", skiprows=1)
    return t[:, 0], t[:, 1:]


NM, CMF = table("cie1931_2deg_cmf_1nm.csv")
TAU = np.ones_like(NM)
TAU[0] = TAU[-1] = 0.5
K = np.sum(TAU * CMF[:, 1])


def xyz(values, wavelengths):
    s = np.interp(NM, wavelengths, values, left=0.0, right=0.0)
    return (s * TAU) @ CMF / K


def xyz_of_xy(x, y):
    return np.array([x / y, 1.0, (1 - x - y) / y])


def rgb_to_xyz(primaries, white):
    p = np.stack([xyz_of_xy(*xy) for xy in primaries], axis=1)
    return p * np.linalg.solve(p, xyz_of_xy(*white))


def bradford(src, dst):
    b = np.array([[0.8951, 0.2664, -0.1614], [-0.7502, 1.7135, 0.0367], [0.0389, -0.0685, 1.0296]])
    return np.linalg.inv(b) @ np.diag((b @ dst) / (b @ src)) @ b


ACES_WHITE = (0.32168, 0.33767)
SPACES = {  # interop ID: RGB -> XYZ (D65-referred, as the configs adapt)
    "lin_rec709_scene": rgb_to_xyz([(0.64, 0.33), (0.30, 0.60), (0.15, 0.06)], (0.3127, 0.3290)),
    "lin_rec2020_scene": rgb_to_xyz([(0.708, 0.292), (0.170, 0.797), (0.131, 0.046)],
                                    (0.3127, 0.3290)),
    "lin_ap1_scene": bradford(xyz_of_xy(*ACES_WHITE), xyz_of_xy(0.3127, 0.3290))
    @ rgb_to_xyz([(0.713, 0.293), (0.165, 0.830), (0.128, 0.044)], ACES_WHITE),
}


def d_series(cct, wavelengths):
    """CIE 15: the daylight locus and the S0 + M1 S1 + M2 S2 basis (linear between 5 nm)."""
    t = cct * 1.4388 / 1.4380
    x = (-4.6070e9 / t**3 + 2.9678e6 / t**2 + 0.09911e3 / t + 0.244063 if t <= 7000 else
         -2.0064e9 / t**3 + 1.9018e6 / t**2 + 0.24748e3 / t + 0.237040)
    y = -3.000 * x * x + 2.870 * x - 0.275
    m = 0.0241 + 0.2562 * x - 0.7341 * y
    m1, m2 = (-1.3515 - 1.7703 * x + 5.9114 * y) / m, (0.0300 - 31.4424 * x + 30.0717 * y) / m
    nm, s = table("cie_daylight_basis_s0_s1_s2_5nm.csv")
    return np.interp(wavelengths, nm, s[:, 0] + m1 * s[:, 1] + m2 * s[:, 2])


def light_stage(space=None):
    stage = Usd.Stage.CreateInMemory()
    root = stage.DefinePrim("/World", "Xform")
    if space:
        Usd.ColorSpaceAPI.Apply(root).CreateColorSpaceNameAttr(space)
    white = UsdLux.RectLight.Define(stage, "/World/White")
    white.CreateIntensityAttr(3.0)
    white.CreateExposureAttr(-1.0)
    coloured = UsdLux.SphereLight.Define(stage, "/World/Warm")
    coloured.CreateColorAttr(Gf.Vec3f(0.9, 0.5, 0.2))
    coloured.CreateIntensityAttr(10.0)
    return stage


@pytest.mark.parametrize("space", [None, "lin_rec709_scene", "lin_rec2020_scene", "lin_ap1_scene"])
def test_each_light_reproduces_colour_times_intensity_times_two_to_the_exposure(space):
    import spectralize.usd
    records = {r["prim"]: r for r in spectralize.usd.lights(light_stage(space))}
    m = SPACES[space or "lin_rec709_scene"]
    records_basis = records["/World/White"]["basis"]
    if records_basis == "D65":
        d65_nm, d65 = table("cie_illuminant_d65_1nm.csv")
        basis = np.interp(NM, d65_nm, d65[:, 0])
    else:
        basis = d_series(6000, NM)
    # The basis as the spectra have it: its samples on their grid, piecewise linear.
    grid = records["/World/White"]["wavelengths"]
    w_basis = xyz(np.interp(grid, NM, basis), grid)
    balance = (w_basis / w_basis[1]) / (m @ np.ones(3))
    for prim, rgb, scale in [("/World/White", (1, 1, 1), 1.5), ("/World/Warm", (0.9, 0.5, 0.2), 10.0)]:
        r = records[prim]
        assert r["scale"] == scale
        want = balance * (m @ (np.array(rgb) * scale))
        got = xyz(r["values"], r["wavelengths"])
        assert np.max(np.abs(got - want)) / np.max(np.abs(want)) <= 1e-5, (prim, got, want)
    # White light is the D-series illuminant itself (its shape): the CIE D65 table for the
    # D65 spaces, the D-series at 6000 K for ACES (whose white is none: the record says so).
    white = records["/World/White"]
    if space == "lin_ap1_scene":
        assert white["basis"] == "D60" and "no D-series white" in white["basis_reason"]
    else:
        assert white["basis"] == "D65"
    ratio = white["values"] / np.interp(white["wavelengths"], NM, basis)
    assert np.max(np.abs(ratio / ratio.mean() - 1)) <= 1e-6


def test_lights_that_cannot_be_made_are_named():
    import spectralize.usd
    stage = Usd.Stage.CreateInMemory()
    UsdLux.DiskLight.Define(stage, "/Neg").CreateColorAttr(Gf.Vec3f(-0.1, 0.5, 0.5))
    warm = UsdLux.DiskLight.Define(stage, "/Warm")
    warm.CreateEnableColorTemperatureAttr(True)
    warm.CreateColorTemperatureAttr(12000.0)
    odd = UsdLux.DiskLight.Define(stage, "/Odd")  # a space the shipped config has none of
    Usd.ColorSpaceAPI.Apply(odd.GetPrim()).CreateColorSpaceNameAttr("pq_rec2020_display")
    UsdLux.DiskLight.Define(stage, "/Fine")
    records = spectralize.usd.lights(stage)
    failures = {r["prim"]: r["failure"] for r in records if "failure" in r}
    assert "negative" in failures["/Neg"]
    assert "12000 K is outside UsdLux's valid range, 1000..10000 K" in failures["/Warm"]
    assert failures["/Odd"].startswith("</Odd>: ") and "pq_rec2020_display" in failures["/Odd"]
    assert set(failures) == {"/Neg", "/Warm", "/Odd"}  # the others are made
    assert [r["prim"] for r in records if "values" in r] == ["/Fine"]


def planck(nm, kelvin):
    """Planck's law, relative (CIE 015:2018 section 3.1: c2 = 1.4388e-2 m K)."""
    m = np.asarray(nm) * 1e-9
    return m**-5 / np.expm1(1.4388e-2 / (m * kelvin))


def uv(x):
    """CIE 1960 UCS chromaticity."""
    d = x[0] + 15 * x[1] + 3 * x[2]
    return np.array([4 * x[0] / d, 6 * x[1] / d])


def cct(x):
    """The correlated colour temperature: the Planckian radiator nearest in CIE 1960 uv (a
    golden-section search over 1000..20000 K, to 1e-3 K)."""
    target = uv(x)

    def distance(t):
        return np.hypot(*(uv(xyz(planck(NM, t), NM)) - target))

    lo, hi = 1000.0, 20000.0
    g = (np.sqrt(5) - 1) / 2
    while hi - lo > 1e-3:
        a, b = hi - g * (hi - lo), lo + g * (hi - lo)
        lo, hi = (lo, b) if distance(a) < distance(b) else (a, hi)
    return (lo + hi) / 2


def temperature_stage(space, kelvin=3200.0):
    stage = Usd.Stage.CreateInMemory()
    root = stage.DefinePrim("/World", "Xform")
    if space:
        Usd.ColorSpaceAPI.Apply(root).CreateColorSpaceNameAttr(space)
    for name, colour in (("Tungsten", None), ("Gelled", Gf.Vec3f(0.9, 0.5, 0.2))):
        light = UsdLux.RectLight.Define(stage, "/World/" + name)
        light.CreateEnableColorTemperatureAttr(True)
        light.CreateColorTemperatureAttr(kelvin)
        light.CreateIntensityAttr(4.0)
        light.CreateExposureAttr(0.5)
        if colour is not None:
            light.CreateColorAttr(colour)
    return stage


@pytest.mark.parametrize("space", [None, "lin_rec709_scene", "lin_rec2020_scene", "lin_ap1_scene"])
def test_a_colour_temperature_is_plancks_law_its_cct_and_its_colour_multiplies_it(space):
    import spectralize.usd
    records = {r["prim"]: r for r in spectralize.usd.lights(temperature_stage(space))}
    scale = 4.0 * 2**0.5
    white = records["/World/Tungsten"]
    assert white["color_temperature"] == 3200.0 and white["basis"] == "3200K"
    grid, values = white["wavelengths"], white["values"]
    # Its shape is Planck's law at 3200 K; its luminance UsdLux's (Y = intensity x 2^exposure).
    ratio = values / planck(grid, 3200.0)
    assert np.max(np.abs(ratio / ratio.mean() - 1)) <= 1e-6
    got = xyz(values, grid)
    assert abs(got[1] / scale - 1) <= 1e-5
    assert abs(cct(got) - 3200.0) <= 1.0
    # A color multiplies the radiator's RGB in the rendering space (white-balanced to the
    # rendering illuminant as the other lights are): the test's own matrices and D-series.
    m = SPACES[space or "lin_rec709_scene"]
    basis = d_series(6000, NM) if space == "lin_ap1_scene" else np.interp(
        NM, *[c.ravel() for c in table("cie_illuminant_d65_1nm.csv")])
    w_basis = xyz(np.interp(grid, NM, basis), grid)
    balance = (w_basis / w_basis[1]) / (m @ np.ones(3))
    rgb_t = np.linalg.solve(m, got / scale / balance)
    want = balance * (m @ (np.array([0.9, 0.5, 0.2]) * rgb_t * scale))
    gelled = xyz(records["/World/Gelled"]["values"], grid)
    assert np.max(np.abs(gelled - want)) / np.max(np.abs(want)) <= 1e-5, (gelled, want)


def test_an_animated_light_has_a_spectrum_per_time_each_exact_at_its_time():
    # Inputs sampled at different times: a spectrum at every time any of them is sampled, each
    # the colour x intensity x 2^exposure the light has at that time (OpenUSD's value
    # resolution: a colour interpolated linearly between its samples, held after the last),
    # never the fallback white of its default time.
    import spectralize.usd
    stage = Usd.Stage.CreateInMemory()
    warm = UsdLux.SphereLight.Define(stage, "/Warm")
    warm.CreateColorAttr().Set(Gf.Vec3f(0.9, 0.5, 0.2), 1.0)
    warm.GetColorAttr().Set(Gf.Vec3f(0.2, 0.5, 0.9), 10.0)
    warm.CreateIntensityAttr(2.0)
    warm.CreateExposureAttr().Set(0.0, 1.0)
    warm.GetExposureAttr().Set(1.0, 5.0)
    tungsten = UsdLux.RectLight.Define(stage, "/Tungsten")
    tungsten.CreateEnableColorTemperatureAttr(True)
    tungsten.CreateColorTemperatureAttr().Set(2700.0, 0.0)
    tungsten.GetColorTemperatureAttr().Set(5000.0, 24.0)
    records = {r["prim"]: r for r in spectralize.usd.lights(stage)}
    m = SPACES["lin_rec709_scene"]
    d65_nm, d65 = table("cie_illuminant_d65_1nm.csv")
    warm_r = records["/Warm"]
    grid = warm_r["wavelengths"]
    w_basis = xyz(np.interp(grid, d65_nm, d65[:, 0]), grid)
    balance = (w_basis / w_basis[1]) / (m @ np.ones(3))
    assert warm_r["times"] == [1.0, 5.0, 10.0] and len(warm_r["values"]) == 3
    at_5 = np.array([0.9, 0.5, 0.2]) + 4 / 9 * (np.array([0.2, 0.5, 0.9]) - [0.9, 0.5, 0.2])
    for row, (rgb, scale) in zip(warm_r["values"], [((0.9, 0.5, 0.2), 2.0), (at_5, 4.0),
                                                    ((0.2, 0.5, 0.9), 4.0)]):
        want = balance * (m @ (np.array(rgb) * scale))
        got = xyz(row, grid)
        assert np.max(np.abs(got - want)) / np.max(np.abs(want)) <= 1e-5, (got, want)
    t_r = records["/Tungsten"]
    assert t_r["times"] == [0.0, 24.0]
    assert [s["basis"] for s in t_r["samples"]] == ["2700K", "5000K"]
    for row, kelvin in zip(t_r["values"], (2700.0, 5000.0)):
        ratio = row / planck(t_r["wavelengths"], kelvin)
        assert np.max(np.abs(ratio / ratio.mean() - 1)) <= 1e-6
        assert abs(cct(xyz(row, t_r["wavelengths"])) - kelvin) <= 1.0


def test_an_animated_light_that_goes_wrong_at_one_time_is_named_with_the_time():
    import spectralize.usd
    stage = Usd.Stage.CreateInMemory()
    light = UsdLux.DiskLight.Define(stage, "/Flicker")
    light.CreateIntensityAttr().Set(1.0, 0.0)
    light.GetIntensityAttr().Set(-1.0, 12.0)
    (record,) = spectralize.usd.lights(stage)
    assert record["failure"] == \
        "</Flicker>: at time 12: a negative colour or intensity: no light has it"
    assert "values" not in record


def test_a_colours_own_colour_space_metadata_is_the_lights_space():
    # inputs:color's colorSpace metadata says more than the UsdColorSpaceAPI of its prim: the
    # colour is read in Rec.2020 and reproduced as the test's Rec.2020 matrix says.
    import spectralize.usd
    stage = Usd.Stage.CreateInMemory()
    Usd.ColorSpaceAPI.Apply(stage.DefinePrim("/World")).CreateColorSpaceNameAttr("lin_ap1_scene")
    light = UsdLux.SphereLight.Define(stage, "/World/Lamp")
    light.CreateColorAttr(Gf.Vec3f(0.9, 0.5, 0.2)).SetColorSpace("lin_rec2020_scene")
    (r,) = spectralize.usd.lights(stage)
    assert r["colorspace"] == "lin_rec2020_scene" and r["basis"] == "D65"
    assert r["colorspace_reason"] == "colorSpace 'lin_rec2020_scene' of </World/Lamp>.inputs:color"
    m = SPACES["lin_rec2020_scene"]
    d65_nm, d65 = table("cie_illuminant_d65_1nm.csv")
    w_basis = xyz(np.interp(r["wavelengths"], d65_nm, d65[:, 0]), r["wavelengths"])
    want = (w_basis / w_basis[1]) / (m @ np.ones(3)) * (m @ np.array([0.9, 0.5, 0.2]))
    got = xyz(r["values"], r["wavelengths"])
    assert np.max(np.abs(got - want)) / np.max(np.abs(want)) <= 1e-5


def test_the_rendering_space_of_the_render_settings_gives_white_its_illuminant():
    # RenderSettings' renderingColorSpace is the rendering space (Hydra's: the prim the
    # stage's renderSettingsPrimPath names, else the only one): white light is the D-series at
    # its white, and a colour in the light's own space (Linear Rec.709, undeclared) is
    # reproduced white-balanced to that illuminant, as the test's matrices say.
    from pxr import UsdRender
    import spectralize.usd
    stage = light_stage()
    UsdRender.Settings.Define(stage, "/Render/Final").CreateRenderingColorSpaceAttr(
        "lin_ap1_scene")
    records = {r["prim"]: r for r in spectralize.usd.lights(stage)}
    white, warm = records["/World/White"], records["/World/Warm"]
    assert white["basis"] == "D60" and white["colorspace"] == "lin_rec709_scene"
    assert white["rendering_colorspace"] == "lin_ap1_scene"
    assert "</Render/Final>" in white["basis_reason"]
    grid = white["wavelengths"]
    ratio = white["values"] / np.interp(grid, NM, d_series(6000, NM))
    assert np.max(np.abs(ratio / ratio.mean() - 1)) <= 1e-6  # white light is D60 itself
    m = SPACES["lin_rec709_scene"]
    w_basis = xyz(np.interp(grid, NM, d_series(6000, NM)), grid)
    want = (w_basis / w_basis[1]) / (m @ np.ones(3)) * (m @ (np.array([0.9, 0.5, 0.2]) * 10.0))
    got = xyz(warm["values"], grid)
    assert np.max(np.abs(got - want)) / np.max(np.abs(want)) <= 1e-5
    # A second RenderSettings and none named: neither is the rendering space (said so) ...
    UsdRender.Settings.Define(stage, "/Render/Preview").CreateRenderingColorSpaceAttr(
        "lin_rec2020_scene")
    white = {r["prim"]: r for r in spectralize.usd.lights(stage)}["/World/White"]
    assert white["basis"] == "D65" and "rendering_colorspace" not in white
    assert "2 RenderSettings prims and no renderSettingsPrimPath names one" in white["basis_reason"]
    # ... until the stage names one.
    stage.SetMetadata("renderSettingsPrimPath", "/Render/Final")
    white = {r["prim"]: r for r in spectralize.usd.lights(stage)}["/World/White"]
    assert white["basis"] == "D60" and "renderSettingsPrimPath" in white["basis_reason"]


def test_a_portal_light_is_given_no_emission_of_its_own():
    # A PortalLight guides a DomeLight's light through a window; it emits none itself, so it
    # gets no emission spectrum (nor a failure), and the dome does.
    import spectralize.usd
    stage = Usd.Stage.CreateInMemory()
    UsdLux.DomeLight.Define(stage, "/Sky")
    UsdLux.PortalLight.Define(stage, "/Sky/Window").CreateColorAttr(Gf.Vec3f(1.0, 0.9, 0.8))
    records = {r["prim"]: r for r in spectralize.usd.lights(stage)}
    assert "values" in records["/Sky"]
    window = records["/Sky/Window"]
    assert "values" not in window and "failure" not in window
    assert "PortalLight emits nothing of its own" in window["not_made"]


def test_a_light_with_a_texture_has_a_tint_flat_for_white():
    # UsdLux multiplies a light's texture by its colour x intensity x 2^exposure; the texture's
    # spectral file holds the emission, so the light's spectrum is a tint: flat for white (the
    # intensity), a colour exact under the equal-energy white (XYZ scaling from the space's
    # white, the test's matrices and 1 nm integration).
    import spectralize.usd
    stage = Usd.Stage.CreateInMemory()
    sky = UsdLux.DomeLight.Define(stage, "/Sky")
    sky.CreateTextureFileAttr("sky.exr")
    sky.CreateIntensityAttr(2.0)
    tv = UsdLux.RectLight.Define(stage, "/Tv")
    tv.CreateTextureFileAttr("tv.png")
    tv.CreateColorAttr(Gf.Vec3f(0.9, 0.5, 0.2))
    tv.CreateExposureAttr(1.0)
    records = {r["prim"]: r for r in spectralize.usd.lights(stage)}
    white = records["/Sky"]
    assert white["textured"] and white["basis"] == "flat"
    assert np.max(np.abs(np.asarray(white["values"]) - 2.0)) <= 1e-6
    r = records["/Tv"]
    grid = r["wavelengths"]
    m = SPACES["lin_rec709_scene"]
    equal_energy = xyz(np.ones_like(grid), grid)
    want = equal_energy / (m @ np.ones(3)) * (m @ (np.array([0.9, 0.5, 0.2]) * 2.0))
    got = xyz(r["values"], grid)
    assert np.max(np.abs(got - want)) / np.max(np.abs(want)) <= 1e-5, (got, want)
