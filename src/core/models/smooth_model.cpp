#include "core/models/smooth_model.h"

namespace spectralize {

SmoothModel::SmoothModel(const ModelContext& context)
    : solver_(context.columns, Roughness::of_length(context.curvature_nm, context.step_nm)),
      paper_(context) {}

ModelSolution SmoothModel::solve(const Xyz& t, double upper) const {
  SmoothSpectrum smooth = solver_.solve(t, upper);
  bool restarted = false;
  if (!smooth.converged) {
    // Rare: targets hugging the gamut boundary (the mapping leaves them 1e-6 inside the locus),
    // where the fast phase cycles and the solver's own projection to a feasible start stalls.
    // The paper model's spectrum is within the bounds and exact (or within 1e-6 of it, for the
    // dark purples where its projection stalls; the primal phase's first full step makes it
    // exact): start the primal phase there.
    const ModelSolution paper = paper_.solve(t, upper);
    Xyz xyz;
    for (std::size_t i = 0; i < paper.values.size(); ++i)
      xyz = xyz + paper.values[i] * solver_.columns()[i];
    if (paper.converged || relative_error(xyz, t) <= 1e-6) {
      smooth = solver_.solve(t, upper, paper.values);
      restarted = true;
    }
  }
  ModelSolution s;
  s.values = std::move(smooth.values);
  s.converged = smooth.converged;
  s.fallback = smooth.fallback || restarted;
  s.details = {{"iterations", static_cast<double>(smooth.iterations)},
               {"primal_phase", s.fallback ? 1.0 : 0.0, true}};
  return s;
}

ModelInfo smooth_model_info() {
  return {"smooth",
          "the smoothest exact spectrum within the bounds: least slope and curvature",
          {"curvature"},
          [](const ModelContext& c) { return std::make_unique<SmoothModel>(c); }};
}

}  // namespace spectralize
