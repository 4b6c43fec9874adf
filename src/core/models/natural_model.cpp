#include "core/models/natural_model.h"

namespace spectralize {

NaturalModel::NaturalModel(const ModelContext& context)
    : solver_(context.columns, context.step_nm) {}

ModelSolution NaturalModel::solve(const Xyz& t, double upper) const {
  NaturalSpectrum n = solver_.solve(t, upper);
  ModelSolution s;
  s.values = std::move(n.values);
  s.converged = n.converged;
  s.fallback = n.fallback || n.safety_net;
  s.details = {{"iterations", static_cast<double>(n.iterations)},
               {"fallback_weight", n.fallback_weight},
               {"safety_net", n.safety_net ? 1.0 : 0.0, true}};
  return s;
}

ModelInfo natural_model_info() {
  return {"natural",
          "the exact spectrum that is smoothest in its link space (logit for reflectances, log "
          "for lights): bounded by construction, behaves like measured materials",
          {},
          [](const ModelContext& c) { return std::make_unique<NaturalModel>(c); }};
}

}  // namespace spectralize
