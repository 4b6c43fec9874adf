#pragma once
// Independent oracles for the unit tests: colour-space matrices written out (or derived here from
// primaries), and the reference integration of docs/DESIGN.md §3 implemented again from its
// definition, so that no expected value comes from the code under test.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <span>
#include <string>
#include <vector>

#include "spectralize/core/colorimetry.h"
#include "spectralize/core/error.h"
#include "spectralize/core/sample_weights.h"
#include "spectralize/core/spectralizer.h"
#include "spectralize/core/wavelength_grid.h"
#include "spectralize/core/xyz.h"

namespace spectralize::test {

// --- 3x3 matrices in double ---

using Mat3 = std::array<std::array<double, 3>, 3>;

inline Xyz mul(const Mat3& m, const Xyz& v) {
  return {m[0][0] * v.X + m[0][1] * v.Y + m[0][2] * v.Z,
          m[1][0] * v.X + m[1][1] * v.Y + m[1][2] * v.Z,
          m[2][0] * v.X + m[2][1] * v.Y + m[2][2] * v.Z};
}

inline Mat3 matmul(const Mat3& a, const Mat3& b) {
  Mat3 c{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) c[i][j] += a[i][k] * b[k][j];
  return c;
}

inline double det3(const Mat3& m) {
  return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
         m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
         m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

// Inverse by the adjugate (cofactors / determinant).
inline Mat3 inverse(const Mat3& m) {
  const double d = det3(m);
  Mat3 r{};
  r[0][0] = (m[1][1] * m[2][2] - m[1][2] * m[2][1]) / d;
  r[0][1] = (m[0][2] * m[2][1] - m[0][1] * m[2][2]) / d;
  r[0][2] = (m[0][1] * m[1][2] - m[0][2] * m[1][1]) / d;
  r[1][0] = (m[1][2] * m[2][0] - m[1][0] * m[2][2]) / d;
  r[1][1] = (m[0][0] * m[2][2] - m[0][2] * m[2][0]) / d;
  r[1][2] = (m[0][2] * m[1][0] - m[0][0] * m[1][2]) / d;
  r[2][0] = (m[1][0] * m[2][1] - m[1][1] * m[2][0]) / d;
  r[2][1] = (m[0][1] * m[2][0] - m[0][0] * m[2][1]) / d;
  r[2][2] = (m[0][0] * m[1][1] - m[0][1] * m[1][0]) / d;
  return r;
}

/// The matrix as the core's row-major frame (m[3 * row + column], core/mat3.h).
inline std::array<double, 9> frame_of(const Mat3& m) {
  std::array<double, 9> f;
  for (int i = 0; i < 9; ++i) f[i] = m[i / 3][i % 3];
  return f;
}

/// m . (r, g, b): the XYZ of an RGB colour.
inline Xyz rgb(const Mat3& m, double r, double g, double b) {
  return mul(m, Xyz{r, g, b});
}

/// XYZ of chromaticity (x, y) at luminance Y.
inline Xyz xyz_from_xy(double x, double y, double Y = 1.0) {
  return {x / y * Y, Y, (1 - x - y) / y * Y};
}

/// Linear Rec.709 (sRGB primaries, D65) -> CIE XYZ.
inline constexpr Mat3 kRec709ToXyz = {
    {{0.41239079926595948, 0.35758433938387796, 0.18048078840183429},
     {0.21263900587151036, 0.71516867876775593, 0.07219231536073372},
     {0.01933081871559185, 0.11919477979462599, 0.95053215224966058}}};

/// Linear Rec.2020 (D65) -> CIE XYZ.
inline constexpr Mat3 kRec2020ToXyz = {
    {{0.63695804830129129, 0.14461690358620837, 0.16888097516417206},
     {0.26270021201126703, 0.67799807151887102, 0.05930171646986195},
     {0.0, 0.02807269304908751, 1.06098505771079091}}};

/// The D65 white of the OCIO config, Y = 1.
inline Xyz d65_white() {
  return xyz_from_xy(0.3127, 0.3290);
}

/// RGB -> XYZ of a space from its primaries and white (the normalised primary matrix).
inline Mat3 rgb_to_xyz(double xr, double yr, double xg, double yg, double xb, double yb, double xw,
                       double yw) {
  const Xyz r = xyz_from_xy(xr, yr), g = xyz_from_xy(xg, yg), b = xyz_from_xy(xb, yb);
  const Mat3 p = {{{r.X, g.X, b.X}, {r.Y, g.Y, b.Y}, {r.Z, g.Z, b.Z}}};
  const Xyz s = mul(inverse(p), xyz_from_xy(xw, yw));
  Mat3 m = p;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) m[i][j] *= s[j];
  return m;
}

/// Bradford chromatic adaptation from white `from` to white `to` (both XYZ).
inline Mat3 bradford(const Xyz& from, const Xyz& to) {
  const Mat3 b = {
      {{0.8951, 0.2664, -0.1614}, {-0.7502, 1.7135, 0.0367}, {0.0389, -0.0685, 1.0296}}};
  const Xyz cf = mul(b, from), ct = mul(b, to);
  const Mat3 d = {{{ct.X / cf.X, 0, 0}, {0, ct.Y / cf.Y, 0}, {0, 0, ct.Z / cf.Z}}};
  return matmul(inverse(b), matmul(d, b));
}

/// ACEScg (AP1 primaries, ACES white) -> CIE XYZ adapted to D65 by Bradford.
inline Mat3 acescg_to_xyz_d65() {
  const Mat3 ap1 = rgb_to_xyz(0.713, 0.293, 0.165, 0.830, 0.128, 0.044, 0.32168, 0.33767);
  return matmul(bradford(xyz_from_xy(0.32168, 0.33767), d65_white()), ap1);
}

/// ACES2065-1 (AP0 primaries, the ACES white) to XYZ adapted to D65 by Bradford, as ACEScg.
inline Mat3 aces2065_to_xyz_d65() {
  const Mat3 ap0 = rgb_to_xyz(0.7347, 0.2653, 0.0, 1.0, 0.0001, -0.0770, 0.32168, 0.33767);
  return matmul(bradford(xyz_from_xy(0.32168, 0.33767), d65_white()), ap0);
}

// --- The reference integration of docs/DESIGN.md §3, written from its definition ---

/// Value at `nm` of the piecewise-linear spectrum through `values` at start + i*step, zero
/// outside [start, start + (n-1) step] (a table point within 1e-9 nm of an end counts as on it).
inline double linear_spectrum(double start, double step, std::span<const double> values,
                              double nm) {
  const std::size_t n = values.size();
  const double end = start + static_cast<double>(n - 1) * step;
  if (nm < start - 1e-9 || nm > end + 1e-9) return 0.0;
  // Interval [a, a + step] holding nm, then linear interpolation between its end samples.
  const double u = std::floor((nm - start) / step);
  const std::size_t i = static_cast<std::size_t>(std::clamp(u, 0.0, static_cast<double>(n - 2)));
  const double a = start + static_cast<double>(i) * step;
  const double t = std::clamp((nm - a) / step, 0.0, 1.0);
  return (1 - t) * values[i] + t * values[i + 1];
}

/// Un-normalised trapezoid sums over 360..830 nm at 1 nm of cmf * E * spectrum (E == nullptr:
/// emission). `values` are on the grid (start, step).
inline Xyz raw_integral(double start, double step, std::span<const double> values,
                        const Observer& obs, const std::vector<double>* illuminant) {
  Xyz s;
  for (int nm = 360; nm <= 830; ++nm) {
    const std::size_t k = static_cast<std::size_t>(nm - 360);
    const double tau = (nm == 360 || nm == 830) ? 0.5 : 1.0;
    const double v =
        linear_spectrum(start, step, values, nm) * (illuminant ? (*illuminant)[k] : 1.0);
    s.X += tau * v * obs.cmf[0][k];
    s.Y += tau * v * obs.cmf[1][k];
    s.Z += tau * v * obs.cmf[2][k];
  }
  return s;
}

/// K = sum tau ybar over the whole 1 nm table: the emission normalisation (docs/DESIGN.md §3).
inline double y_integral(const Observer& obs) {
  double s = 0;
  for (int nm = 360; nm <= 830; ++nm)
    s += ((nm == 360 || nm == 830) ? 0.5 : 1.0) * obs.cmf[1][static_cast<std::size_t>(nm - 360)];
  return s;
}

/// The normalisation of docs/DESIGN.md §3: emission K; reflectance the raw Y of rho == 1 on the
/// grid, so that rho == 1 has Y = 1.
inline double reference_norm(const WavelengthGrid& grid, const Observer& obs,
                             const std::vector<double>* illuminant) {
  if (!illuminant) return y_integral(obs);
  const std::vector<double> ones(grid.size(), 1.0);
  return raw_integral(grid.start(), grid.step(), ones, obs, illuminant).Y;
}

/// Normalised XYZ of a spectrum on `grid` (emission when illuminant == nullptr).
inline Xyz reference_xyz(const WavelengthGrid& grid, std::span<const double> values,
                         const Observer& obs, const std::vector<double>* illuminant) {
  EXPECT_EQ(values.size(), grid.size());
  return (1.0 / reference_norm(grid, obs, illuminant)) *
         raw_integral(grid.start(), grid.step(), values, obs, illuminant);
}

/// The default grid's weights (a reflectance under D65, or emission) and the reference
/// integration of a spectrum on that grid: what the core's model and solver tests start from.
struct DefaultGridWeights {
  WavelengthGrid grid;
  Illuminant d65 = Illuminant::get("D65");
  bool reflectance;
  SampleWeights w;
  explicit DefaultGridWeights(bool refl)
      : reflectance(refl), w(grid, Observer::get("cie1931"), refl ? &d65 : nullptr) {}
  /// The grid's wavelengths, nm.
  std::vector<double> wavelengths() const {
    std::vector<double> nm;
    for (std::size_t i = 0; i < grid.size(); ++i) nm.push_back(grid[i]);
    return nm;
  }
  /// The XYZ of samples `s` by the reference integration (docs/DESIGN.md §3).
  Xyz colour(const std::vector<double>& s) const {
    return reference_xyz(grid, s, Observer::get("cie1931"), reflectance ? &d65.spd : nullptr);
  }
};

/// XYZ of an illuminant itself (a light with that SPD), integrated on the full 1 nm table
/// (un-normalised).
inline Xyz illuminant_xyz(const Observer& obs, const Illuminant& il) {
  Xyz s;
  for (int nm = 360; nm <= 830; ++nm) {
    const std::size_t k = static_cast<std::size_t>(nm - 360);
    const double tau = (nm == 360 || nm == 830) ? 0.5 : 1.0;
    for (int c = 0; c < 3; ++c) s[c] += tau * obs.cmf[c][k] * il.spd[k];
  }
  return s;
}

/// The XYZ of a spectrum on `s`'s grid by the reference integration: emission, or a reflectance
/// under `s`'s reference illuminant (rho == 1 at Y = 1).
inline Xyz reference_xyz(const SpectralizerSettings& s, std::span<const double> values) {
  const Observer& obs = Observer::get(s.observer);
  if (s.mode == Mode::emission) return reference_xyz(s.grid, values, obs, nullptr);
  const Illuminant e = Illuminant::get(s.illuminant);
  return reference_xyz(s.grid, values, obs, &e.spd);
}

/// The white balance of a reflectance (docs/DESIGN.md §3), per component: the reference white
/// (rho == 1 on `s`'s grid under its illuminant) over the D65 white.
inline Xyz white_balance(const SpectralizerSettings& s) {
  const std::vector<double> ones(s.grid.size(), 1.0);
  const Xyz w = reference_xyz(s, ones);
  const Xyz d65 = d65_white();
  return {w.X / d65.X, w.Y / d65.Y, w.Z / d65.Z};
}

/// Chromaticity (x, y) of an XYZ.
inline std::array<double, 2> chromaticity(const Xyz& c) {
  return {c.X / c.sum(), c.Y / c.sum()};
}

/// max |a - b| / max |b| (componentwise).
inline double rel_err(const Xyz& a, const Xyz& b) {
  return std::max({std::abs(a.X - b.X), std::abs(a.Y - b.Y), std::abs(a.Z - b.Z)}) / b.max_abs();
}

/// max_i |a_i - b_i| / max_i |b_i| of two spectra.
inline double rel_err(std::span<const double> a, std::span<const double> b) {
  double diff = 0, scale = 0;
  for (std::size_t i = 0; i < b.size(); ++i) {
    diff = std::max(diff, std::abs(a[i] - b[i]));
    scale = std::max(scale, std::abs(b[i]));
  }
  return diff / scale;
}

/// The message of the spectralize::Error `fn` throws, or "" when it throws none.
template <typename Fn>
std::string error_message(Fn&& fn) {
  try {
    fn();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

/// Runs `fn`, expects spectralize::Error whose message contains every one of `words`.
template <typename Fn>
void expect_error_mentioning(Fn&& fn, std::vector<std::string> words, const std::string& what) {
  try {
    fn();
    ADD_FAILURE() << what << ": no Error thrown";
  } catch (const Error& e) {
    const std::string msg = e.what();
    for (const auto& w : words) {
      EXPECT_NE(msg.find(w), std::string::npos)
          << what << ": message '" << msg << "' lacks '" << w << "'";
    }
  } catch (const std::exception& e) {
    ADD_FAILURE() << what << ": threw a non-spectralize exception: " << e.what();
  }
}

}  // namespace spectralize::test
