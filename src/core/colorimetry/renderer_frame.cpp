#include "core/colorimetry/renderer_frame.h"

#include <charconv>
#include <cmath>
#include <vector>

#include "core/decimal_number.h"
#include "spectralize/core/error.h"

namespace spectralize {

namespace {

std::vector<std::string_view> fields_of(std::string_view text) {
  std::vector<std::string_view> out;
  for (std::size_t at = 0;;) {
    const std::size_t comma = text.find(',', at);
    std::string_view f = text.substr(at, comma == std::string_view::npos ? comma : comma - at);
    while (!f.empty() && f.front() == ' ') f.remove_prefix(1);
    while (!f.empty() && f.back() == ' ') f.remove_suffix(1);
    out.push_back(f);
    if (comma == std::string_view::npos) return out;
    at = comma + 1;
  }
}

double number(std::string_view f, std::string_view text) {
  try {
    return decimal_number(f);
  } catch (const Error& e) {
    throw Error(quote(text) + ": " + e.what());
  }
}

std::string shortest(double v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

}  // namespace

RendererMatrix RendererMatrix::parse(std::string_view text) {
  const std::vector<std::string_view> f = fields_of(text);
  RendererMatrix r;
  if (f.size() == 9) {
    Mat3 m{};
    for (int k = 0; k < 9; ++k) m[k] = number(f[k], text);
    if (!(std::abs(det(m)) > 1e-9))
      throw Error("'" + std::string(text) + "': the matrix is singular (no RGB space has it)");
    if (!(m[3] + m[4] + m[5] > 0))
      throw Error("'" + std::string(text) + "': white (1, 1, 1) has no positive luminance Y");
    r.matrix = m;
    return r;
  }
  if (f.size() == 7) {
    for (int k = 0; k < 6; ++k) {
      r.primaries[k] = number(f[k], text);
      if (!(std::abs(r.primaries[k]) <= 2))
        throw Error("'" + std::string(text) + "': a chromaticity coordinate is " +
                    std::string(f[k]) + " (primaries are CIE x, y pairs)");
    }
    r.white = Illuminant::get(f[6]).name;
    (void)rgb_to_xyz_of_primaries(r.primaries, Xyz{0.95, 1, 1.09});  // a triangle at all?
    return r;
  }
  throw Error("'" + std::string(text) +
              "': give the nine numbers of the matrix (row-major, m00,m01,...,m22) or the "
              "primaries and an illuminant (xr,yr,xg,yg,xb,yb,D65)");
}

std::string RendererMatrix::to_string() const {
  std::string s;
  auto add = [&s](std::string_view field) {
    if (!s.empty()) s.push_back(',');
    s.append(field);
  };
  if (matrix)
    for (double v : *matrix) add(shortest(v));
  else
    for (double v : primaries) add(shortest(v));
  if (!matrix) add(white);
  return s;
}

Mat3 RendererMatrix::resolve(const Observer& observer) const {
  if (matrix) return *matrix;
  return rgb_to_xyz_of_primaries(primaries, illuminant_white(Illuminant::get(white), observer));
}

Xyz illuminant_white(const Illuminant& illuminant, const Observer& observer) {
  double xyz[3] = {0, 0, 0};
  for (std::size_t k = 0; k < ReferenceTable::kSize; ++k) {
    const double w = ReferenceTable::trapezoid(k) * illuminant.spd[k];
    for (int c = 0; c < 3; ++c) xyz[c] += w * observer.cmf[c][k];
  }
  return {xyz[0] / xyz[1], 1.0, xyz[2] / xyz[1]};
}

Mat3 rgb_to_xyz_of_primaries(const std::array<double, 6>& xy, const Xyz& white) {
  // Columns: each primary's XYZ at Y = 1, then scaled so that their sum is the white.
  Xyz p[3];
  for (int i = 0; i < 3; ++i) {
    const double x = xy[2 * i], y = xy[2 * i + 1];
    if (!(y > 1e-9 || y < -1e-9)) throw Error("a primary with y = 0 has no XYZ at unit luminance");
    p[i] = {x / y, 1.0, (1 - x - y) / y};
  }
  const Mat3 unscaled = from_columns(p[0], p[1], p[2]);
  if (!(std::abs(det(unscaled)) > 1e-9)) throw Error("the primaries span no triangle");
  const Xyz s = mul(inverse(unscaled), white);
  return from_columns(Xyz{p[0].X * s.X, p[0].Y * s.X, p[0].Z * s.X},
                      Xyz{p[1].X * s.Y, p[1].Y * s.Y, p[1].Z * s.Y},
                      Xyz{p[2].X * s.Z, p[2].Y * s.Z, p[2].Z * s.Z});
}

}  // namespace spectralize
