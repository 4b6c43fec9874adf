#pragma once
// The natural model (beyond the paper, docs/DESIGN.md §6): among all exact spectra, the one
// whose link z is smoothest, with x = upper * (tanh z + 1) / 2 for reflectances and x = e^z for
// lights: Burns' bounded smoothest reflectance and its log-space twin for lights. Bounded by
// construction, no tuned parameter; near the gamut boundary a continuous, counted fallback
// (NaturalSolver).

#include "core/solvers/natural_solver.h"
#include "spectralize/core/spectrum_model.h"

namespace spectralize {

class NaturalModel final : public SpectrumModel {
 public:
  /// Prepares the facets of the solid and the locus cone for the depth. Cost: O(N^3) once
  /// (~1 ms at 5 nm, ~0.1 s at 1 nm).
  explicit NaturalModel(const ModelContext& context);

  /// The spectrum of smoothest link; details: iterations, fallback_weight (0 in the natural
  /// zone, rising to 1 at the gamut boundary), safety_net (the non-continuous last resort ran).
  /// Thread-safe. Cost: ~20 us (emission) to ~27 us (reflectance) median at 5 nm.
  ModelSolution solve(const Xyz& target, double upper) const override;

 private:
  NaturalSolver solver_;
};

/// The registry entry of the natural model. Cost: O(1).
ModelInfo natural_model_info();

}  // namespace spectralize
