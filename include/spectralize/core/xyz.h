#pragma once
// A CIE XYZ tristimulus triple and the few vector operations the solvers need.

#include <algorithm>
#include <cmath>

namespace spectralize {

struct Xyz {
  double X = 0, Y = 0, Z = 0;

  double operator[](int i) const { return i == 0 ? X : (i == 1 ? Y : Z); }
  double& operator[](int i) { return i == 0 ? X : (i == 1 ? Y : Z); }
  friend Xyz operator+(Xyz a, Xyz b) { return {a.X + b.X, a.Y + b.Y, a.Z + b.Z}; }
  friend Xyz operator-(Xyz a, Xyz b) { return {a.X - b.X, a.Y - b.Y, a.Z - b.Z}; }
  friend Xyz operator*(double s, Xyz a) { return {s * a.X, s * a.Y, s * a.Z}; }
  friend bool operator==(const Xyz&, const Xyz&) = default;
  /// Largest absolute component. Cost: O(1).
  double max_abs() const { return std::max({std::abs(X), std::abs(Y), std::abs(Z)}); }
  /// X + Y + Z. Cost: O(1).
  double sum() const { return X + Y + Z; }
  /// True when every component is finite. Cost: O(1).
  bool finite() const { return std::isfinite(X) && std::isfinite(Y) && std::isfinite(Z); }
};

inline double dot(Xyz a, Xyz b) {
  return a.X * b.X + a.Y * b.Y + a.Z * b.Z;
}
inline Xyz cross(Xyz a, Xyz b) {
  return {a.Y * b.Z - a.Z * b.Y, a.Z * b.X - a.X * b.Z, a.X * b.Y - a.Y * b.X};
}
/// Componentwise product (diagonal scaling, e.g. white balance). Cost: O(1).
inline Xyz hadamard(Xyz a, Xyz b) {
  return {a.X * b.X, a.Y * b.Y, a.Z * b.Z};
}

/// Relative round-trip error max|got - want| / max|want| (0 when want is zero and got is too).
inline double relative_error(Xyz got, Xyz want) {
  double scale = want.max_abs();
  double diff = (got - want).max_abs();
  if (scale == 0) return diff == 0 ? 0.0 : INFINITY;
  return diff / scale;
}

}  // namespace spectralize
