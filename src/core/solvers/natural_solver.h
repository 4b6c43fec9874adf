#pragma once
// The natural exact model: among all spectra with W x = target, the one whose *link* z is
// smoothest, where x = upper * sigma(z) for reflectances (sigma(z) = (tanh z + 1) / 2, so
// 0 < x < upper for every z) and x = exp(z) for lights (upper = +inf). The roughness is
// sum (z_{i+1} - z_i)^2 (Burns' bounded smoothest reflectance, no tuned parameter): measured
// reflectances are smooth in logit space, and a sigmoid keeps the bounds by construction.
//
// Solved by Newton's method on the Lagrangian, whose Hessian is tridiagonal plus a rank-3
// border, so each step costs O(N) (banded LDL^T, Schur complement on the 3 multipliers).
//
// Near the gamut boundary the natural spectrum tends to a step function (z -> +-inf), so the
// model is used up to a fixed depth of the gamut (kNaturalDepth of the way from the grey of the
// same luminance to the boundary). Deeper targets take the natural link z0 of the target
// pulled back to that depth and project it onto the real target in the link's own geometry
// (z = z0 + W^T nu: a Kullback-Leibler projection for lights, a binary-entropy one for
// reflectances): continuous across the threshold (an exact spectrum projects to itself), inside
// the bounds by construction, and exact everywhere strictly inside the gamut. The same
// projection removes the last rounding of every natural solve.

#include <cstddef>
#include <limits>
#include <span>
#include <vector>

#include "spectralize/core/xyz.h"

namespace spectralize {

struct NaturalSpectrum {
  std::vector<double> values;
  bool converged = false;      // exact (<= 1e-12 relative) and the natural Newton converged
  bool fallback = false;       // deeper than the natural zone: projected from the pulled target
  double fallback_weight = 0;  // 0 inside the natural zone, rising to 1 at the gamut boundary
  bool safety_net = false;     // the link projection stalled; least squares made it exact
                               // (not continuous with neighbours; seen only within ~1e-6 of
                               // the locus, docs/DESIGN.md §6)
  int iterations = 0;          // Newton iterations plus projection iterations
};

class NaturalSolver {
 public:
  /// Depth (0 at the grey of the target's luminance, 1 at the gamut boundary) up to which the
  /// natural spectrum is used unchanged. Not fitted to data: measured reflectances (ColorChecker,
  /// AMPAS 190) lie at depth <= 0.94; up to 1 - 1e-3 Newton converged on every colour tested
  /// (docs/DESIGN.md §6). A robustness margin, not a fitted parameter.
  static constexpr double kNaturalDepth = 0.999;
  /// The most iterations solve() takes (NaturalSpectrum::iterations), whatever the target: 80
  /// Newton steps, 200 of the link projection and twice 200 of the bounded projection.
  static constexpr int kMaxIterations = 680;

  /// Prepares the facets of the reflectance solid and of the spectral locus for N samples with
  /// weight vectors `columns` on a grid of step `step_nm`. Cost: O(N^3) once (~1 ms at 5 nm).
  NaturalSolver(std::span<const Xyz> columns, double step_nm, double natural_depth = kNaturalDepth);

  /// The natural spectrum with W x = target and 0 <= x <= upper (upper = +inf: a light, x >= 0).
  /// The target must be inside the gamut (the solid {W x: 0 <= x <= upper} or the locus cone);
  /// outside, the bounded best effort is returned with converged = false. Never throws; never
  /// loops forever (iterations capped). Thread-safe. Cost: O(N) per Newton step, typically 5..15
  /// steps, plus O(N^2) for the depth test (~23 us median at 5 nm, ~1 us of it the depth test;
  /// the exact depth, ~5 us, only beyond the natural zone).
  NaturalSpectrum solve(const Xyz& target,
                        double upper = std::numeric_limits<double>::infinity()) const;

  /// Depth of a target in the gamut along the ray from the grey (reflectance) or white (light)
  /// of the same luminance Y: 0 on that ray, 1 on the boundary, > 1 outside; +inf if Y <= 0 or
  /// (reflectance) Y >= upper. Continuous inside the gamut. Cost: O(N^2) (the facets).
  double depth(const Xyz& target, double upper) const;

  /// sum (z_{i+1} - z_i)^2 / h of a spectrum's link z (the roughness the model minimises, in
  /// the units of the integral of z'^2 over nm); +inf if a sample is on a bound. Cost: O(N).
  double roughness(std::span<const double> x, double upper) const;

  std::size_t size() const { return columns_.size(); }

 private:
  std::vector<Xyz> columns_;
  double step_nm_;
  double natural_depth_;
  Xyz white_;  // W . 1
  // Facets of the solid {W rho: 0 <= rho <= 1} (normal n, n . p <= pos and -n . p <= neg) and of
  // the locus cone (n . p <= 0), one per pair of generators spanning a supporting plane.
  std::vector<double> solid_nx_, solid_ny_, solid_nz_;  // the normals, as structure of arrays
  std::vector<double> solid_pos_, solid_neg_;
  std::vector<Xyz> cone_normals_;
};

}  // namespace spectralize
