#include "core/models/paper_model.h"

#include <algorithm>

#include "core/solvers/bounded_projection.h"

namespace spectralize {

namespace {

// Upper bounds that cap the edge bands at 0.9 of the interior mean: 0.9 leaves room for the
// projection's small change of that mean.
std::vector<double> edge_caps(const EdgeBands& bands, std::span<const double> spectrum,
                              double upper) {
  std::vector<double> bounds(spectrum.size(), upper);
  const double cap = 0.9 * bands.interior_mean(spectrum);
  for (std::size_t i : bands.edge_samples()) bounds[i] = std::min(upper, cap);
  return bounds;
}

}  // namespace

PaperModel::PaperModel(const ModelContext& context)
    : columns_(context.columns.begin(), context.columns.end()),
      solver_(context.columns, context.wavelengths),
      filter_(context.filter) {}

ModelSolution PaperModel::solve(const Xyz& t, double upper) const {
  // The paper's average of admissible partial solutions, edge-filtered.
  const PaperSpectrum paper = solver_.solve(t, filter_);

  // Exact to double precision: the paper's average is exact in exact arithmetic, so a tiny
  // relative polish suffices. If that fails, or the spectrum exceeds the bound, the fallback is
  // the closest spectrum that is exact, non-negative and within the bound.
  Projection proj;
  proj.values = paper.values;
  proj.converged = polish_exact(columns_, proj.values, t);
  const double peak = *std::max_element(proj.values.begin(), proj.values.end());
  const bool bounded = peak > upper;
  if (!proj.converged || bounded) proj = project_exact(columns_, paper.values, t, upper);

  // Filter "auto": if even the ladder's last step leaves an edge peak (saturated colours that
  // need light near an end of the range), cap the edge bands below the interior mean by the
  // same exact projection, and keep the result only if it is peak-free.
  bool capped = false;
  const EdgeBands& bands = solver_.edge_bands();
  if (filter_.kind() == EdgeFilter::Kind::automatic && proj.converged &&
      !bands.free_of_peaks(proj.values)) {
    Projection c = project_exact(columns_, proj.values, t, edge_caps(bands, proj.values, upper));
    if (c.converged && bands.free_of_peaks(c.values)) {
      proj = std::move(c);
      capped = true;
    }
  }
  ModelSolution s;
  s.values = std::move(proj.values);
  s.converged = proj.converged;
  s.fallback = bounded || capped;
  s.details = {{"admissible", static_cast<double>(paper.admissible)},
               {"dropped", static_cast<double>(paper.dropped)},
               {"bounded", bounded ? 1.0 : 0.0, true},
               {"edge_capped", capped ? 1.0 : 0.0, true}};
  return s;
}

ModelInfo paper_model_info() {
  return {"paper",
          "the paper's average of the admissible partial solutions, edge-filtered",
          {"filter"},
          [](const ModelContext& c) { return std::make_unique<PaperModel>(c); }};
}

}  // namespace spectralize
