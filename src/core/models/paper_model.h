#pragma once
// The paper's model (Zhdanov & Potemin, docs/DESIGN.md §2): the average of the admissible
// partial solutions after the edge-peak filter, polished to double-precision exactness, with the
// exact bounded projection as the fallback when a reflectance exceeds 1 (docs/DESIGN.md §5).

#include <memory>

#include "core/solvers/paper_solver.h"
#include "spectralize/core/spectrum_model.h"

namespace spectralize {

class PaperModel final : public SpectrumModel {
 public:
  /// Prepares the partial-solution kernel for the context's weights. Cost: O(N).
  explicit PaperModel(const ModelContext& context);

  /// The filtered average, made exact and bounded; details: admissible (L), dropped (K),
  /// bounded (the projection changed it to meet the bound), edge_capped (see the guide's
  /// "Edge filter", docs/guide/conventions.md). Thread-safe. Cost: O(N^2 + L), ~40 us at 5 nm.
  ModelSolution solve(const Xyz& target, double upper) const override;

 private:
  std::vector<Xyz> columns_;
  PaperSolver solver_;
  EdgeFilter filter_;
};

/// The registry entry of the paper model. Cost: O(1).
ModelInfo paper_model_info();

}  // namespace spectralize
