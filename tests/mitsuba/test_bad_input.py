"""Bad input to the plugins is a Python exception naming the file (or the property) and the
reason, never a crash: an RGB or mono variant, a missing or corrupt table, a missing or
non-spectral EXR, reflectances given to the environment map, a data map, contradictory or
unknown properties. Mitsuba passes a plugin's exception on inside its own, with the text."""
import numpy as np
import pytest

from conftest import EXE, IMAGES, use, write_image


def load(mi, d):
    return mi.load_dict(d)


def refused(mi, d, *words):
    with pytest.raises(Exception) as e:
        load(mi, d)
    for w in words:
        assert w in str(e.value), (w, str(e.value))


def test_rgb_and_mono_variants_are_refused_naming_the_variant(mi):
    import spectralize.mitsuba
    try:
        for variant in ("llvm_ad_rgb", "llvm_ad_mono", "scalar_rgb"):
            mi.set_variant(variant)
            with pytest.raises(RuntimeError, match=variant + ".*not spectra.*llvm_ad_spectral"):
                spectralize.mitsuba.register()
    finally:
        use(mi, "llvm_ad_spectral")


def test_tables_that_cannot_be_used_are_named(mi, tmp_path):
    colour = [0.2, 0.4, 0.6]
    refused(mi, {"type": "spectralize_rgb", "color": colour, "table": str(tmp_path / "no.spztab")},
            "no.spztab")
    bad = tmp_path / "bad.spztab"
    bad.write_bytes(b"SPZTABLE" + bytes(2000))
    refused(mi, {"type": "spectralize_rgb", "color": colour, "table": str(bad)}, "bad.spztab")
    cut = tmp_path / "cut.spztab"
    import spectralize
    whole = tmp_path / "whole.spztab"
    spectralize.table(str(whole), wavelengths="400:700:20")
    cut.write_bytes(whole.read_bytes()[:5000])
    refused(mi, {"type": "spectralize_rgb", "color": colour, "table": str(cut)}, "cut.spztab",
            "truncated")
    # A light's table for a surface texture.
    light = tmp_path / "light.spztab"
    spectralize.table(str(light), mode="emission", wavelengths="400:700:20")
    refused(mi, {"type": "spectralize_rgb", "color": colour, "table": str(light)},
            "light.spztab", "emission table")


def test_files_that_are_not_spectral_images_are_named(mi, tmp_path):
    refused(mi, {"type": "spectral_bitmap", "filename": str(tmp_path / "none.exr")}, "none.exr")
    rgb = tmp_path / "rgb.exr"
    write_image(rgb, np.full((4, 4, 3), 0.5, np.float32))
    refused(mi, {"type": "spectral_bitmap", "filename": str(rgb)}, "rgb.exr",
            "no spectral bands")
    junk = tmp_path / "junk.exr"
    junk.write_bytes(b"v/1\x01" + bytes(100))
    refused(mi, {"type": "spectral_envmap", "filename": str(junk)}, "junk.exr")
    refused(mi, {"type": "spectralize_rgb", "filename": str(tmp_path / "none.png")}, "none.png")


def test_reflectances_are_not_an_environment_map(mi, tmp_path):
    import subprocess
    out = tmp_path / "surface.exr"
    p = subprocess.run([EXE, str(IMAGES / "colorchecker_srgb8.png"), "-o", str(out), "-q"],
                       capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    refused(mi, {"type": "spectral_envmap", "filename": str(out)}, "surface.exr",
            "reflectances")


def test_a_data_map_has_no_spectra(mi, tmp_path):
    normal = tmp_path / "brick_normal.png"
    write_image(normal, np.full((4, 4, 3), 128, np.uint8), dtype="uint8")
    refused(mi, {"type": "spectralize_rgb", "filename": str(normal)}, "brick_normal.png",
            "not colour")


def test_contradictory_and_unknown_properties_are_named(mi):
    refused(mi, {"type": "spectralize_rgb"}, "filename or a color")
    refused(mi, {"type": "spectralize_rgb", "color": [0.5, 0.5, 0.5],
                 "filename": str(IMAGES / "colorchecker_srgb8.png")}, "filename or a color")
    refused(mi, {"type": "spectralize_rgb", "color": [0.5, 0.5, 0.5], "mode": "light"},
            "mode 'light'")
    refused(mi, {"type": "spectralize_rgb", "filename": str(IMAGES / "colorchecker_srgb8.png"),
                 "filter_type": "cubic"}, "filter_type 'cubic'")
    refused(mi, {"type": "spectralize_rgb", "filename": str(IMAGES / "colorchecker_srgb8.png"),
                 "colorspace": "No Such Space"}, "No Such Space")
    # A misspelt property is not ignored: Mitsuba names what no plugin read.
    refused(mi, {"type": "spectralize_rgb", "color": [0.5, 0.5, 0.5], "filtre_type": "nearest"},
            "filtre_type")
