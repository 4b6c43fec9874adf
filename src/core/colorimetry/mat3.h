#pragma once
// 3x3 matrices in double, row-major, acting on Xyz triples: colour-space frames (RGB -> XYZ) and
// the affine maps of the exact table's simplices (docs/DESIGN.md §14).

#include <array>
#include <cmath>

#include "spectralize/core/xyz.h"

namespace spectralize {

/// Row-major: m[3 * row + column].
using Mat3 = std::array<double, 9>;

inline constexpr Mat3 kIdentity3 = {1, 0, 0, 0, 1, 0, 0, 0, 1};

/// m . v. Cost: O(1).
inline Xyz mul(const Mat3& m, const Xyz& v) {
  return {m[0] * v.X + m[1] * v.Y + m[2] * v.Z, m[3] * v.X + m[4] * v.Y + m[5] * v.Z,
          m[6] * v.X + m[7] * v.Y + m[8] * v.Z};
}

/// a . b. Cost: O(1).
inline Mat3 mul(const Mat3& a, const Mat3& b) {
  Mat3 c{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) c[3 * i + j] += a[3 * i + k] * b[3 * k + j];
  return c;
}

/// The determinant. Cost: O(1).
inline double det(const Mat3& m) {
  return m[0] * (m[4] * m[8] - m[5] * m[7]) - m[1] * (m[3] * m[8] - m[5] * m[6]) +
         m[2] * (m[3] * m[7] - m[4] * m[6]);
}

/// The inverse by cofactors (the caller checks that det(m) is not 0). Cost: O(1).
inline Mat3 inverse(const Mat3& m) {
  const double d = det(m);
  return {(m[4] * m[8] - m[5] * m[7]) / d, (m[2] * m[7] - m[1] * m[8]) / d,
          (m[1] * m[5] - m[2] * m[4]) / d, (m[5] * m[6] - m[3] * m[8]) / d,
          (m[0] * m[8] - m[2] * m[6]) / d, (m[2] * m[3] - m[0] * m[5]) / d,
          (m[3] * m[7] - m[4] * m[6]) / d, (m[1] * m[6] - m[0] * m[7]) / d,
          (m[0] * m[4] - m[1] * m[3]) / d};
}

/// The matrix whose columns are a, b, c. Cost: O(1).
inline Mat3 from_columns(const Xyz& a, const Xyz& b, const Xyz& c) {
  return {a.X, b.X, c.X, a.Y, b.Y, c.Y, a.Z, b.Z, c.Z};
}

/// diag(d) . m: row i scaled by d[i]. Cost: O(1).
inline Mat3 scale_rows(const Xyz& d, const Mat3& m) {
  return {d.X * m[0], d.X * m[1], d.X * m[2], d.Y * m[3], d.Y * m[4],
          d.Y * m[5], d.Z * m[6], d.Z * m[7], d.Z * m[8]};
}

}  // namespace spectralize
