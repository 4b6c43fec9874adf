#pragma once
// The two gamuts of docs/DESIGN.md §5, as exact half-space descriptions in XYZ:
// - the spectral locus of a grid: the cone {W phi : phi >= 0} spanned by the sample weights;
// - the reflectance solid: the zonotope {W rho : 0 <= rho <= 1}.
// A target outside is moved toward a white of the same luminance until it is inside.

#include <span>
#include <vector>

#include "spectralize/core/xyz.h"

namespace spectralize {

class ConvexGamut {
 public:
  /// The cone spanned by the weights (emission). Cost: O(N^3) once (N^2 candidate facets).
  static ConvexGamut spectral_locus(std::span<const Xyz> weights);
  /// The zonotope {W rho : 0 <= rho <= 1} (reflectance). Cost: O(N^3) once.
  static ConvexGamut reflectance_solid(std::span<const Xyz> weights);

  /// True when `t` satisfies every facet to 1e-12 of |t| (scale-free: near black the gamuts
  /// are cones). Cost: O(facets).
  bool contains(const Xyz& t) const;
  /// The largest s in [0, 1] with from + s (to - from) inside; `from` must be inside.
  /// Cost: O(facets).
  double max_step(const Xyz& from, const Xyz& to) const;
  /// Number of facet half-spaces. Cost: O(1).
  std::size_t facets() const { return offsets_.size(); }
  /// Facet f: its unit outward normal and offset (inside: n . t <= offset). Cost: O(1).
  Xyz normal(std::size_t f) const { return {nx_[f], ny_[f], nz_[f]}; }
  double offset(std::size_t f) const { return offsets_[f]; }
  /// The gamut's magnitude (the largest component of the sum of its generators). Cost: O(1).
  double scale() const { return scale_; }

 private:
  void add(const Xyz& normal, double offset);
  std::vector<double> nx_, ny_, nz_;  // unit outward normals n_f (structure of arrays)
  std::vector<double> offsets_;       // inside: n_f . t <= offsets_f
  double scale_ = 1;                  // typical magnitude of the gamut, for tolerances
};

}  // namespace spectralize
