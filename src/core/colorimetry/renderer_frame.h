#pragma once
// A renderer's own RGB -> XYZ (docs/DESIGN.md §14, "Renderer conventions"): `spectralize table
// --rgb-to-xyz` makes a table whose spectra reproduce exactly the XYZ a renderer's matrix gives,
// under the table's observer and illuminant, without the D65 white balance of the project's
// own conventions (§3). Renderers build that matrix from their colour space's primaries and the
// white of their own illuminant spectrum (pbrt-v4's RGBColorSpace, Mitsuba 3's sRGB): given as
// nine numbers, or as the primaries and an illuminant whose white this computes the same way.

#include <optional>
#include <string>
#include <string_view>

#include "core/colorimetry/mat3.h"
#include "spectralize/core/colorimetry.h"

namespace spectralize {

/// A renderer's matrix as given: nine numbers (row-major), or the xy of the red, green and
/// blue primaries and the illuminant whose white (1, 1, 1) is.
struct RendererMatrix {
  std::optional<Mat3> matrix;
  std::array<double, 6> primaries{};  // xr, yr, xg, yg, xb, yb
  std::string white;                  // an illuminant name (Illuminant::get)

  /// Parses "m00,m01,...,m22" or "xr,yr,xg,yg,xb,yb,ILLUMINANT"; throws Error saying what is
  /// wrong (not finite, a singular matrix, a primary outside the xy triangle of real colours,
  /// an unknown illuminant). Cost: O(1) (an illuminant's table for the second form).
  static RendererMatrix parse(std::string_view text);
  /// The canonical text, parseable by parse(): shortest round-trip numbers. Cost: O(1).
  std::string to_string() const;
  /// The matrix: as given, or from the primaries and the illuminant's white under `observer`.
  /// Cost: O(reference table).
  Mat3 resolve(const Observer& observer) const;
};

/// The XYZ of an illuminant's light under an observer, Y = 1: the trapezoid rule on the 1 nm
/// tables over 360-830 nm, as renderers integrate their illuminant spectra. Cost: O(table).
Xyz illuminant_white(const Illuminant& illuminant, const Observer& observer);

/// The RGB -> XYZ matrix of primaries (x, y of red, green, blue) whose (1, 1, 1) is `white`
/// (the textbook construction, as pbrt-v4's RGBColorSpace builds it). Throws Error for
/// primaries that span no triangle. Cost: O(1).
Mat3 rgb_to_xyz_of_primaries(const std::array<double, 6>& xy, const Xyz& white);

}  // namespace spectralize
