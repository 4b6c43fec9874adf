#pragma once
// The smooth model (beyond the paper, docs/DESIGN.md §6): among all exact spectra within the
// bounds, the one of least roughness sum (x_{i+1} - x_i)^2 + (tau/h)^2 sum (second differences)^2,
// solved by SmoothSolver's active-set method.

#include "core/models/paper_model.h"
#include "core/solvers/smooth_solver.h"
#include "spectralize/core/spectrum_model.h"

namespace spectralize {

class SmoothModel final : public SpectrumModel {
 public:
  /// Prepares the banded roughness matrix for the context (tau = context.curvature_nm).
  /// Cost: O(N).
  explicit SmoothModel(const ModelContext& context);

  /// The least-rough exact bounded spectrum; details: iterations, primal_phase (the fast phase
  /// cycled and the primal phase finished). Thread-safe. Cost: ~16 us (emission) to ~26 us
  /// (reflectance) at 5 nm.
  ModelSolution solve(const Xyz& target, double upper) const override;

 private:
  SmoothSolver solver_;
  PaperModel paper_;  // a feasible start where the fast phase fails
};

/// The registry entry of the smooth model. Cost: O(1).
ModelInfo smooth_model_info();

}  // namespace spectralize
