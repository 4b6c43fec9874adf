"""Ahead of Mitsuba's own uplift: the measured ColorChecker (the project's Ohta data) as an 8-bit
sRGB texture (its colours under D65, by the test's own integration), rendered under CIE A, FL2
and FL11 (the project's tables) with Mitsuba's bitmap and with spectralize_rgb (the default
model and natural). Each patch's CIEDE2000 against the measured reflectance under the same
light, each relative to its own white (a unit reflectance rendered, or integrated, under that
light): spectralize's median is below bitmap's under every light. The table of median / p95 /
max is what the guide shows."""
import numpy as np
import pytest

from conftest import COLOUR, RGB_TO_XYZ, delta_e2000, flat_quad, lab, srgb_encode, write_image

LIGHTS = ("A", "FL2", "FL11")
RESULTS = {}


def light_dict(name):
    nm, values = COLOUR.illuminant(name)
    keep = (nm >= 360) & (nm <= 830)
    nm, values = nm[keep], values[keep]
    # Mitsuba's irregular spectrum: "wavelengths" and "values" as comma-separated lists.
    return {"type": "irregular", "wavelengths": ",".join("%g" % x for x in nm),
            "values": ",".join("%g" % (v / values.max()) for v in values)}


@pytest.fixture(scope="module")
def chart(tmp_path_factory):
    rho, names = COLOUR.colorchecker()
    d65 = COLOUR.on_grid(*COLOUR.illuminant("D65"))
    white = COLOUR.xyz(d65)
    xyz = COLOUR.xyz(rho * d65) / white[1]
    rgb = xyz @ np.linalg.inv(RGB_TO_XYZ).T  # linear Rec.709, white -> (1, 1, 1)
    path = tmp_path_factory.mktemp("chart") / "colorchecker_srgb.png"
    write_image(path, srgb_encode(rgb).reshape(4, 6, 3), dtype="uint8")
    return path, rho, names


def test_the_chart_under_other_lights(mi, chart):
    path, rho, names = chart
    models = {"bitmap": {"type": "bitmap", "filename": str(path), "filter_type": "nearest"},
              "spectralize_rgb": {"type": "spectralize_rgb", "filename": str(path),
                                  "filter_type": "nearest"},
              "spectralize_rgb natural": {"type": "spectralize_rgb", "filename": str(path),
                                          "filter_type": "nearest", "model": "natural"}}
    for light in LIGHTS:
        spd = COLOUR.on_grid(*COLOUR.illuminant(light))
        ref_white = COLOUR.xyz(spd)
        ref_lab = lab(COLOUR.xyz(rho * spd), ref_white)
        ld = light_dict(light)
        white_rgb = flat_quad(mi, {"type": "uniform", "value": 1.0}, 1, 1, spp=4096,
                              sampler="stratified", light=ld)[0, 0]
        white_xyz = RGB_TO_XYZ @ white_rgb
        for name, tex in models.items():
            rgb = flat_quad(mi, tex, 6, 4, spp=4096, sampler="stratified", light=ld)
            de = delta_e2000(lab(rgb.reshape(24, 3) @ RGB_TO_XYZ.T, white_xyz), ref_lab)
            RESULTS[(light, name)] = (np.median(de), np.percentile(de, 95), de.max())
    print("\nCIEDE2000 against the measured ColorChecker (24 patches): median / p95 / max")
    for light in LIGHTS:
        print("  %-5s " % light + "  ".join("%s %.2f / %.2f / %.2f" % ((name,) + RESULTS[(light, name)])
                                           for name in models))
    for light in LIGHTS:
        for name in ("spectralize_rgb", "spectralize_rgb natural"):
            assert RESULTS[(light, name)][0] < RESULTS[(light, "bitmap")][0], (light, name, RESULTS)
