#pragma once
// The spectrum-model interface (docs/DESIGN.md §6): a model chooses one spectrum among all the
// exact bounded ones of a colour. The Spectralizer around it does everything the models share
// (white balance, gamut mapping, the emission basis, the white snap); a model only solves
//   W s = target,  0 <= s <= upper
// for a target strictly inside the gamut. Models are registered by name in model_registry.cpp.

#include <cstddef>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "spectralize/core/edge_filter.h"
#include "spectralize/core/xyz.h"

namespace spectralize {

/// A number a model reports about one solve, e.g. the paper model's "admissible" count.
struct ModelDetail {
  std::string name;  // a JSON key: lower case with underscores
  double value = 0;
  bool boolean = false;  // print as true/false rather than as a number
};

/// One solve of a model.
struct ModelSolution {
  std::vector<double> values;        // s: the spectrum divided by the emission basis
  bool converged = false;            // false: the model's own optimality or exactness failed
  bool fallback = false;             // the model's stated fallback produced (part of) it
  std::vector<ModelDetail> details;  // model-specific diagnostics, in print order
};

/// What a model is built for: the solver's weight columns (already multiplied by the emission
/// basis), the wavelengths of the samples and the model's own parameters.
struct ModelContext {
  std::span<const Xyz> columns;         // W: one XYZ weight vector per sample
  std::span<const double> wavelengths;  // nm, increasing, one per sample
  double step_nm = 5;                   // grid step
  EdgeFilter filter;                    // the paper model's edge filter
  double curvature_nm = 50;             // the smooth model's tau
};

class SpectrumModel {
 public:
  virtual ~SpectrumModel() = default;
  /// An exact spectrum s with W s = target and 0 <= s <= upper for a target strictly inside
  /// the gamut (the Spectralizer maps everything else first). Never throws. Thread-safe.
  /// Cost: the model's; tens of microseconds at 5 nm for the shipped ones.
  virtual ModelSolution solve(const Xyz& target, double upper) const = 0;
};

/// A registered model: its name, a one-line description for --help, the settings it reads
/// (besides the shared ones) and how to build it.
struct ModelInfo {
  std::string_view name;
  std::string_view summary;
  std::vector<std::string_view> settings;  // e.g. {"filter"} for the paper model
  std::function<std::unique_ptr<SpectrumModel>(const ModelContext&)> make;

  /// True when this model reads the setting `name`. Cost: O(settings).
  bool uses(std::string_view setting) const;
};

/// Every registered model, in the order --help lists them. Cost: O(1).
const std::vector<ModelInfo>& spectrum_models();
/// The model registered as `name`; throws Error naming the valid ones. Cost: O(models).
const ModelInfo& find_model(std::string_view name);
/// The model used when none is chosen. Cost: O(1).
std::string_view default_model_name();

/// A registered model, resolved once from its name and passed on as this value (never looked
/// up by name again); compared by identity. Constructible from a name, so that
/// `settings.model = "paper"` reads as it says.
class RegisteredModel {
 public:
  /// The default model. Cost: O(models).
  RegisteredModel() : RegisteredModel(default_model_name()) {}
  /// The model registered as `name`; throws Error naming the valid ones. Cost: O(models).
  RegisteredModel(std::string_view name) : info_(&find_model(name)) {}
  /// As above, for a C string. Cost: O(models).
  RegisteredModel(const char* name) : RegisteredModel(std::string_view(name)) {}
  /// As above, for a string. Cost: O(models).
  RegisteredModel(const std::string& name) : RegisteredModel(std::string_view(name)) {}
  /// What is registered: name, summary, settings, factory. Cost: O(1).
  const ModelInfo& info() const { return *info_; }
  /// The registered name ("exemplar"). Cost: O(1).
  std::string_view name() const { return info_->name; }
  /// True when the model reads the setting `name` (ModelInfo::uses). Cost: O(settings).
  bool uses(std::string_view setting) const { return info_->uses(setting); }
  /// The same model. Cost: O(1).
  friend bool operator==(const RegisteredModel& a, const RegisteredModel& b) {
    return a.info_ == b.info_;
  }

 private:
  const ModelInfo* info_;
};

}  // namespace spectralize
