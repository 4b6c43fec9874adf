#pragma once
// Colours shared by the benchmarks and the edge-filter study.

#include <cmath>

#include "core/xyz.h"

namespace bench {

/// Linear Rec.709 (D65) RGB to CIE XYZ, from the primaries. Cost: O(1).
inline spectralize::Xyz rec709(double r, double g, double b) {
  return {0.41239079926595948 * r + 0.35758433938387796 * g + 0.18048078840183429 * b,
          0.21263900587151036 * r + 0.71516867876775593 * g + 0.07219231536073372 * b,
          0.01933081871559185 * r + 0.11919477979462599 * g + 0.95053215224966058 * b};
}

/// The sRGB decoding curve (IEC 61966-2-1). Cost: O(1).
inline double srgb_decode(double v) {
  return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
}

}  // namespace bench
