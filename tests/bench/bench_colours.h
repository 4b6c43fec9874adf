#pragma once
// Colours shared by the benchmarks and the edge-filter study.

#include <array>
#include <cmath>

#include "spectralize/core/xyz.h"

namespace bench {

/// Linear Rec.709 (D65) RGB to CIE XYZ, from the primaries, rows X, Y, Z.
inline constexpr std::array<std::array<double, 3>, 3> kRec709ToXyz = {
    {{0.41239079926595948, 0.35758433938387796, 0.18048078840183429},
     {0.21263900587151036, 0.71516867876775593, 0.07219231536073372},
     {0.01933081871559185, 0.11919477979462599, 0.95053215224966058}}};

/// Linear Rec.709 (D65) RGB to CIE XYZ. Cost: O(1).
inline spectralize::Xyz rec709(double r, double g, double b) {
  const auto& m = kRec709ToXyz;
  return {m[0][0] * r + m[0][1] * g + m[0][2] * b, m[1][0] * r + m[1][1] * g + m[1][2] * b,
          m[2][0] * r + m[2][1] * g + m[2][2] * b};
}

/// The sRGB decoding curve (IEC 61966-2-1). Cost: O(1).
inline double srgb_decode(double v) {
  return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
}

}  // namespace bench
