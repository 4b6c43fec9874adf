#include "core/models/exemplar_model.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/solvers/bounded_projection.h"
#include "spectralize/core/colorimetry.h"

namespace spectralize {

namespace {

// A reflectance's XYZ under the model's weights.
Xyz colour_of(std::span<const Xyz> columns, std::span<const double> rho) {
  Xyz sum;
  for (std::size_t i = 0; i < columns.size(); ++i) sum = sum + rho[i] * columns[i];
  return sum;
}

}  // namespace

std::vector<std::string> development_set_files() {
  return {"colorchecker_n_ohta_5nm.csv", "ampas_rawtoaces_190_patches_5nm.csv"};
}

std::vector<std::vector<double>> development_reflectances(std::span<const double> wavelengths,
                                                          std::span<const std::string> sets) {
  std::vector<std::vector<double>> out;
  for (const std::string& file : development_set_files()) {
    if (!sets.empty() && std::find(sets.begin(), sets.end(), file) == sets.end()) continue;
    const EmbeddedTable table = embedded_table(file);  // one parse for all its columns
    const std::vector<double>& nm = table.wavelengths;
    for (const std::vector<double>& values : table.columns) {
      std::vector<double> rho(wavelengths.size());
      for (std::size_t i = 0; i < wavelengths.size(); ++i) {
        const double l = wavelengths[i];
        const auto j =
            static_cast<std::size_t>(std::upper_bound(nm.begin(), nm.end(), l) - nm.begin());
        if (j == 0) {
          rho[i] = values.front();
        } else if (j >= nm.size()) {
          rho[i] = values.back();
        } else {
          const double t = (l - nm[j - 1]) / (nm[j] - nm[j - 1]);
          rho[i] = (1 - t) * values[j - 1] + t * values[j];
        }
      }
      out.push_back(std::move(rho));
    }
  }
  return out;
}

ExemplarModel::ExemplarModel(const ModelContext& context)
    : ExemplarModel(context, development_reflectances(context.wavelengths)) {}

ExemplarModel::ExemplarModel(const ModelContext& context,
                             std::vector<std::vector<double>> exemplars)
    : columns_(context.columns.begin(), context.columns.end()),
      solver_(context.columns, context.step_nm) {
  for (const Xyz& c : columns_) white_ = white_ + c;
  for (std::vector<double>& rho : exemplars) {
    // The distance is to the material's measured colour; the blend uses its shape within the
    // bounds.
    const Lab lab = to_lab(colour_of(columns_, rho), white_);
    for (double& v : rho) v = std::clamp(v, 0.0, 1.0);
    exemplars_.push_back({std::move(rho), lab, ciede2000_metric(lab)});
  }
}

ModelSolution ExemplarModel::solve(const Xyz& t, double upper) const {
  NaturalSpectrum n = solver_.solve(t, upper);
  ModelSolution s;
  s.values = std::move(n.values);
  s.converged = n.converged;
  s.fallback = n.fallback || n.safety_net;
  int count = 0;
  double sum = 0;
  bool failed = false;
  // Lights, and colours no exemplar is near, keep the natural spectrum.
  if (std::isfinite(upper)) {
    const Lab lab = to_lab((1 / upper) * t, white_);
    const double h2 = kRadius * kRadius;
    std::vector<double> blend;
    for (const Exemplar& e : exemplars_) {
      const double d2 = e.metric.squared(lab.L - e.lab.L, lab.a - e.lab.a, lab.b - e.lab.b);
      if (!(d2 < h2)) continue;
      const double u = 1 - d2 / h2;
      const double w = u * u * u;
      if (blend.empty()) {
        blend = s.values;
        for (double& v : blend) v *= kNaturalWeight;
      }
      for (std::size_t i = 0; i < blend.size(); ++i) blend[i] += w * upper * e.rho[i];
      sum += w;
      ++count;
    }
    if (count > 0) {
      for (double& v : blend) v /= kNaturalWeight + sum;
      Projection p = project_exact(columns_, blend, t, upper);
      if (p.converged) {
        s.values = std::move(p.values);
        s.converged = n.converged && relative_error(colour_of(columns_, s.values), t) <= 1e-12;
      } else {
        failed = true;  // keep the natural spectrum (exact), reported
        s.fallback = true;
      }
    }
  }
  s.details = {{"iterations", static_cast<double>(n.iterations)},
               {"fallback_weight", n.fallback_weight},
               {"safety_net", n.safety_net ? 1.0 : 0.0, true},
               {"exemplars", static_cast<double>(count)},
               {"exemplar_weight", count > 0 ? sum / (kNaturalWeight + sum) : 0.0},
               {"projection_failed", failed ? 1.0 : 0.0, true}};
  return s;
}

ModelInfo exemplar_model_info() {
  return {"exemplar",
          "the natural spectrum, but near the colours of measured materials (ColorChecker, AMPAS "
          "190) their measured shapes, made exact: closest to measured materials under other "
          "lights",
          {},
          [](const ModelContext& c) { return std::make_unique<ExemplarModel>(c); }};
}

}  // namespace spectralize
