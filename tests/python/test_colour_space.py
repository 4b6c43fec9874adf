"""spectralize.colour_space(): a space of the config as every command decides it. Oracles:
the published AP1 and Rec.709 primaries and whites, the shipped config's names (its file)."""
import pytest

import spectralize


@pytest.mark.parametrize("given", ["ACEScg", "lin_ap1", "ACES - ACEScg", "lin_ap1_scene"])
def test_a_space_is_found_by_name_alias_or_interop_id(given):
    f = spectralize.colour_space(given)
    assert f["name"] == "ACEScg" and f["interop_id"] == "lin_ap1_scene"
    assert f["encoding"] == "scene-linear" and f["linear"] and not f["data"]
    # AP1 and the ACES white, as the standard gives them.
    assert f["chromaticities"] == pytest.approx(
        [0.713, 0.293, 0.165, 0.830, 0.128, 0.044, 0.32168, 0.33767], abs=1e-6)


def test_what_it_knows_of_other_kinds_of_space():
    srgb = spectralize.colour_space("sRGB - Texture")
    assert (srgb["interop_id"], srgb["linear"]) == ("srgb_rec709_scene", False)
    assert srgb["chromaticities"] == pytest.approx(
        [0.64, 0.33, 0.30, 0.60, 0.15, 0.06, 0.3127, 0.3290], abs=1e-4)
    raw = spectralize.colour_space("Raw")
    assert raw["data"] and raw["chromaticities"] is None


def test_an_unknown_space_or_option_is_refused():
    with pytest.raises(ValueError, match="banana"):
        spectralize.colour_space("banana")
    with pytest.raises((ValueError, TypeError)):
        spectralize.colour_space("ACEScg", mode="emission")
