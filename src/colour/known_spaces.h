#pragma once
// The standard colour spaces spectralize knows without a config (docs/DESIGN.md §9), in one
// place: their primaries and whites (as the standard states them and as a D65-referred config
// sees them), their encodings (transfer curves), the Color Interop Forum's IDs built of the two,
// and the names configs usually give them. A config's own spaces are measured against these
// (colour/colour_space.h); nothing here needs OCIO.

#include <array>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "colour/icc_profile.h"

namespace spectralize {

/// Chromaticities that are the same primaries: the largest difference in CIE xy of any of the
/// eight numbers, after adapting both whites to D65 (docs/DESIGN.md §9).
inline constexpr double kChromaticityTolerance = 2e-3;

/// CIE xy of the D65 white as the standards round it (Rec.709, sRGB, Rec.2020, P3-D65).
inline constexpr float kD65x = 0.3127f, kD65y = 0.3290f;

/// A standard set of primaries and white (red, green, blue, white as CIE xy).
struct KnownPrimaries {
  std::string_view id;           // the interop ID's primaries part: "rec709", "ap1", ...
  std::array<float, 8> native;   // as the standard states them (ACES: the ACES white)
  std::array<float, 8> adapted;  // white Bradford-adapted to D65, as OCIO's configs see them
};

/// A standard encoding: the transfer curve from encoded values to linear light.
struct KnownEncoding {
  std::string_view id;   // the interop ID's curve part: "lin", "srgb", "g22", ...
  IccTransfer transfer;  // what an ICC profile states of it
  /// The curve at `v` (encoded, 0..1) as linear light. Cost: O(1).
  double operator()(double v) const;
};

/// Every standard set of primaries, in the order matches are tried. Cost: O(1).
std::span<const KnownPrimaries> known_primaries();

/// Every standard encoding, in the order a measured curve is matched (linear first; Adobe RGB's
/// 563/256 before the 2.2 it is within 0.2% of). Cost: O(1).
std::span<const KnownEncoding> known_encodings();

/// The standard primaries whose D65-adapted chromaticities are within kChromaticityTolerance of
/// `adapted_xy` (eight numbers, white at D65), or nullptr. Cost: O(known primaries).
const KnownPrimaries* known_primaries_of(const float* adapted_xy);

/// The interop ID of an encoding on known primaries, scene- or display-referred
/// ("srgb_rec709_scene"), when the Color Interop Forum names that combination, else "".
/// Cost: O(known IDs).
std::string known_interop_id(std::string_view encoding, std::string_view primaries,
                             bool display_referred);

/// The shape of the Color Interop Forum's IDs ("<curve>_<primaries>_scene" or "..._display",
/// or "data"), as OIIO 3 writes them in oiio:ColorSpace. Cost: O(length).
bool looks_like_interop_id(std::string_view s);

/// Names configs usually give the space of an interop ID (ACES configs, the shipped one), in
/// the order they are tried; empty when none is known. Cost: O(known IDs).
std::span<const std::string_view> usual_names_of(std::string_view interop_id);

/// `xy` (red, green, blue, white as CIE xy) with the white Bradford-adapted to D65 and the
/// primaries with it: the primaries as a D65-referred config sees them (Rec.709 primaries
/// adapted to D50, as Photoshop writes them, give Rec.709 back). Cost: O(1).
std::array<float, 8> adapt_chromaticities_to_d65(const float* xy);

/// The largest |a[i] - b[i]| of two sets of eight chromaticities. Cost: O(1).
double chromaticity_difference(const float* a, const float* b);

/// The linear interop ID of a file's chromaticities (red, green, blue, white xy) when, adapted
/// to D65, they are a known standard's (Rec.709, Rec.2020, P3-D65, Adobe RGB, AP1, AP0, XYZ)
/// within kChromaticityTolerance, else "". Cost: O(1).
std::string interop_id_of_chromaticities(const float* xy);

}  // namespace spectralize
