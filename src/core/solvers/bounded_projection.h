#pragma once
// The exact bounded fallback: the spectrum closest (least squares) to a starting spectrum among
// all spectra with W x = target and 0 <= x <= upper (docs/DESIGN.md §5's feasible set). Used to
// enforce rho <= 1 when the paper's filter alone does not, and to polish the paper's average to
// double precision exactness.

#include <limits>
#include <span>
#include <vector>

#include "spectralize/core/xyz.h"

namespace spectralize {

struct Projection {
  std::vector<double> values;
  bool converged = false;  // false: target infeasible for the bounds (or iteration cap hit)
  int iterations = 0;
  double residual = 0;  // max |W x - target| / max |target| of the values returned
};

/// How hard the projection works: it stops when max |W x - target| <= tolerance x max |target|;
/// damping x trace(W W^T) regularises the Newton system where few samples are free (larger:
/// steadier steps near the solid's boundary).
struct ProjectionControl {
  double tolerance = 1e-13;
  double damping = 1e-12;
  int max_iterations = 500;
};

/// Solves min ||x - start||^2 s.t. W x = target, 0 <= x <= upper by a globally convergent
/// semismooth Newton method on the 3-dimensional dual (x = clamp(start + W^T nu)). Capped at
/// 500 iterations, so it always returns. Cost: O(N) per iteration, typically 2..10 iterations.
Projection project_exact(std::span<const Xyz> weights, std::span<const double> start,
                         const Xyz& target, double upper = std::numeric_limits<double>::infinity(),
                         const ProjectionControl& control = {});

/// Makes `spectrum` reproduce `target` exactly by the smallest relative change that keeps zeros
/// at zero: x_m *= 1 + c_m.a / s_m with a from one 3x3 solve (the correction is linear in a),
/// repeated to double precision. Returns false, leaving `spectrum` unchanged, if the correction
/// would make a sample negative or the support spans too few directions. Cost: O(N).
bool polish_exact(std::span<const Xyz> weights, std::span<double> spectrum, const Xyz& target);

/// As above with a bound per sample: 0 <= x_m <= upper[m]. Cost: as above.
Projection project_exact(std::span<const Xyz> weights, std::span<const double> start,
                         const Xyz& target, std::span<const double> upper,
                         const ProjectionControl& control = {});

}  // namespace spectralize
