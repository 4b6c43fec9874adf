// The registered spectrum models. Adding a model: its file pair, one line in models() below,
// and its tests (docs/DESIGN.md §6).

#include <algorithm>

#include "core/models/exemplar_model.h"
#include "core/models/natural_model.h"
#include "core/models/paper_model.h"
#include "core/models/smooth_model.h"
#include "spectralize/core/error.h"
#include "spectralize/core/spectrum_model.h"

namespace spectralize {

bool ModelInfo::uses(std::string_view setting) const {
  return std::find(settings.begin(), settings.end(), setting) != settings.end();
}

const std::vector<ModelInfo>& spectrum_models() {
  static const std::vector<ModelInfo> models = {exemplar_model_info(), natural_model_info(),
                                                smooth_model_info(), paper_model_info()};
  return models;
}

// The exemplar model: the winner of the model study by its rule fixed in advance (the best
// worst case over both development sets, cross-validated, six lights, two spaces;
// docs/MODEL_STUDY.md), exact, bounded, continuous and as fast as the natural model it extends.
std::string_view default_model_name() {
  return "exemplar";
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
