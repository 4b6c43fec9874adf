#pragma once
// The smooth exact model (beyond the paper): among all spectra with W x = target and
// 0 <= x <= upper (docs/DESIGN.md §5's feasible set), the one of least roughness x^T H x, where H
// is the Gram matrix of a difference operator (banded). A strictly convex quadratic programme with
// 3 equality constraints and box bounds, solved by a primal-dual active-set method with a
// primal active-set fallback, so it reaches the KKT conditions and always stops.

#include <cstddef>
#include <limits>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "spectralize/core/xyz.h"

namespace spectralize {

/// The roughness a smooth spectrum minimises: slope * sum (x_{i+1} - x_i)^2 + curvature * sum
/// (x_i - 2 x_{i+1} + x_{i+2})^2 (squared first and second differences of the samples).
struct Roughness {
  double slope = 1;
  double curvature = 0;
  /// The discrete form of the integral of x'^2 + tau^2 x''^2 over wavelength on a grid of step
  /// h nm (h^-1 and tau^2 h^-3, scaled by h): the same smoothness on every grid. Cost: O(1).
  static Roughness of_length(double tau_nm, double step_nm) {
    return {1.0, (tau_nm / step_nm) * (tau_nm / step_nm)};
  }
};

struct SmoothSpectrum {
  std::vector<double> values;
  bool converged = false;  // KKT conditions met (else: exact and bounded, but not optimal)
  int iterations = 0;      // active-set iterations, both phases, and the projection's
  bool fallback = false;   // the primal-dual phase cycled; the primal phase finished
};

class SmoothSolver {
 public:
  /// Prepares the banded roughness matrix for N samples with weight vectors `columns`.
  /// Cost: O(N).
  SmoothSolver(std::span<const Xyz> columns, Roughness roughness);

  /// The least-roughness spectrum with W x = target and 0 <= x <= upper. The target must be
  /// feasible (inside the gamut, with some margin); `feasible` is an exact spectrum within the
  /// bounds, used only if the fast phase fails (may be empty: then found by projection).
  /// Never throws; never loops forever (iterations capped). Thread-safe. Cost: O(N) per
  /// iteration, typically 3..10 iterations (~10 us at 5 nm).
  SmoothSpectrum solve(const Xyz& target, double upper = std::numeric_limits<double>::infinity(),
                       std::span<const double> feasible = {}) const;
  /// The most iterations solve() takes for N samples (SmoothSpectrum::iterations), whatever the
  /// target: 40 primal-dual, 500 of the projection to a feasible start, 4 N + 50 primal.
  static constexpr int max_iterations(int samples) { return 40 + 500 + 4 * samples + 50; }

  /// x^T H x of a spectrum (without the tiny ridge): the roughness minimised. Cost: O(N).
  double roughness(std::span<const double> x) const;

  std::size_t size() const { return columns_.size(); }
  /// The weight vectors the spectra must reproduce. Cost: O(1).
  std::span<const Xyz> columns() const { return columns_; }

 private:
  std::vector<Xyz> columns_;
  int band_ = 1;                      // bandwidth of H: 1 (tridiagonal) or 2 (pentadiagonal)
  std::vector<double> h0_, h1_, h2_;  // H's diagonal, first and second off-diagonal
  double ridge_ = 0;                  // added to h0_: makes H positive definite
};

}  // namespace spectralize
