#pragma once
// ICC profiles for the integer formats (TIFF, PNG, JPEG) that have no other slot for a colour
// space (docs/DESIGN.md §9): made by LittleCMS from the space's primaries, white and transfer
// function. The LittleCMS headers stay in icc_profile.cpp.

#include <array>
#include <string>
#include <vector>

namespace spectralize {

/// A transfer function an ICC profile can state exactly.
struct IccTransfer {
  enum Kind { linear, srgb, gamma } kind = linear;
  double exponent = 1;  // for Kind::gamma
};

/// An RGB display profile (ICC v4) with `xy` (red, green, blue, white as CIE xy, as an OpenEXR
/// chromaticities attribute holds them), the transfer `t` on each channel and `description` as
/// its 'desc' tag; empty when LittleCMS cannot make it (degenerate primaries).
/// Cost: ~50 us, ~1 KB.
std::vector<unsigned char> icc_profile(const std::array<float, 8>& xy, const IccTransfer& t,
                                       const std::string& description);

}  // namespace spectralize
