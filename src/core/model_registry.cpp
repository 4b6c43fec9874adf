// The registered spectrum models. Adding a model: its file pair, one line in models() below,
// and its tests (docs/DESIGN.md §6).

#include <algorithm>

#include "core/error.h"
#include "core/exemplar_model.h"
#include "core/natural_model.h"
#include "core/paper_model.h"
#include "core/smooth_model.h"
#include "core/spectrum_model.h"

namespace spectralize {

bool ModelInfo::uses(std::string_view setting) const {
  return std::find(settings.begin(), settings.end(), setting) != settings.end();
}

const std::vector<ModelInfo>& spectrum_models() {
  static const std::vector<ModelInfo> models = {natural_model_info(), exemplar_model_info(),
                                                smooth_model_info(), paper_model_info()};
  return models;
}

// The natural model: exact, bounded, the closest to measured materials under other lights on
// both development sets, never failing and faster than the paper's (README, "Models").
std::string_view default_model_name() {
  return "natural";
}

const ModelInfo& find_model(std::string_view name) {
  std::string valid;
  for (const ModelInfo& m : spectrum_models()) {
    if (m.name == name) return m;
    valid += (valid.empty() ? "" : ", ") + std::string(m.name);
  }
  throw Error("unknown model " + quote(name) + " (valid: " + valid + ")");
}

}  // namespace spectralize
