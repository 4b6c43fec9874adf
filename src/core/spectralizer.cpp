#include "core/spectralizer.h"

#include <algorithm>
#include <cmath>

#include "core/bounded_projection.h"
#include "core/error.h"

namespace spectralize {

namespace {

std::unique_ptr<Illuminant> illuminant_for(const SpectralizerSettings& s) {
  // Resolve the name even in emission mode, so a typo is an error whatever the mode.
  auto il = std::make_unique<Illuminant>(Illuminant::get(s.illuminant));
  if (s.mode == Mode::emission) return nullptr;
  return il;
}

std::vector<double> wavelengths_of(const WavelengthGrid& grid) {
  std::vector<double> nm(grid.size());
  for (std::size_t i = 0; i < nm.size(); ++i) nm[i] = grid[i];
  return nm;
}

double chromaticity_distance(const Xyz& a, const Xyz& b) {
  double sa = a.sum(), sb = b.sum();
  if (!(sa > 0) || !(sb > 0)) return 0;
  return std::hypot(a.X / sa - b.X / sb, a.Y / sa - b.Y / sb);
}

// Fraction of the way back from the boundary: keeps mapped targets strictly inside, where
// the fan of admissible triangles and the bounded projection are well conditioned.
constexpr double kGamutMargin = 1e-6;

// Relative XYZ change up to which a gamut mapping counts as snapping (float input precision).
constexpr double kSnapTolerance = 1e-6;

}  // namespace

std::string_view to_string(Mode mode) {
  return mode == Mode::emission ? "emission" : "reflectance";
}

Mode parse_mode(std::string_view text) {
  if (text == "emission") return Mode::emission;
  if (text == "reflectance") return Mode::reflectance;
  throw Error("unknown mode '" + std::string(text) + "' (valid: emission, reflectance)");
}

std::string_view to_string(Status status) {
  switch (status) {
    case Status::ok:
      return "ok";
    case Status::black:
      return "black";
    case Status::out_of_gamut:
      return "out_of_gamut";
    case Status::invalid:
      return "invalid";
  }
  return "unknown";
}

EdgeFilter default_edge_filter() {
  return EdgeFilter::automatic();
}

Spectralizer::Spectralizer(SpectralizerSettings settings)
    : settings_(std::move(settings)),
      observer_(&Observer::get(settings_.observer)),
      illuminant_(illuminant_for(settings_)),
      weights_(settings_.grid, *observer_, illuminant_.get()),
      solver_(weights_.columns(), wavelengths_of(settings_.grid)),
      gamut_(settings_.mode == Mode::emission ? ConvexGamut::spectral_locus(weights_.columns())
                                              : ConvexGamut::reflectance_solid(weights_.columns())),
      white_balance_{1, 1, 1} {
  if (settings_.mode == Mode::reflectance) {
    Xyz ref = weights_.unit_white();
    white_balance_ = {ref.X / kWhiteD65.X, ref.Y / kWhiteD65.Y, ref.Z / kWhiteD65.Z};
  }
}

std::vector<double> Spectralizer::edge_caps(std::span<const double> spectrum, double upper) const {
  // 0.9 of the interior mean leaves room for the projection's small change of that mean.
  std::vector<double> bounds(settings_.grid.size(), upper);
  const double cap = 0.9 * solver_.interior_mean(spectrum);
  for (std::size_t i : solver_.edge_samples()) bounds[i] = std::min(upper, cap);
  return bounds;
}

Xyz Spectralizer::target_of(const Xyz& xyz_d65) const {
  return hadamard(xyz_d65, white_balance_);
}

SpectrumResult Spectralizer::spectralize(const Xyz& xyz_d65) const {
  SpectrumResult r;
  const std::size_t n = settings_.grid.size();
  r.values.assign(n, 0.0);
  r.input = xyz_d65;
  r.dropped = 0;

  // Reject what no spectrum can mean.
  if (!xyz_d65.finite()) {
    r.status = Status::invalid;
    r.message = "colour has NaN or infinite components";
    return r;
  }
  Xyz t = target_of(xyz_d65);
  if (t == Xyz{}) {
    r.status = Status::black;
    return r;
  }
  if (t.Y < 0) {
    r.status = Status::invalid;
    r.message = "colour has negative luminance (Y < 0)";
    r.target = Xyz{};
    return r;
  }

  // Map out-of-gamut colours toward the white of the same luminance (reflectance: first
  // down to Y = 1, the brightest a reflectance can be).
  const Xyz requested = t;
  if (!gamut_.contains(t)) {
    r.status = Status::out_of_gamut;
    if (settings_.mode == Mode::reflectance && t.Y > 1) t = (1.0 / t.Y) * t;
    Xyz white = settings_.mode == Mode::reflectance ? t.Y * weights_.unit_white() : t.Y * kWhiteD65;
    double s = gamut_.max_step(white, t);
    if (!gamut_.contains(t)) s = std::max(0.0, s - kGamutMargin);
    t = white + s * (t - white);
    r.gamut_distance = chromaticity_distance(requested, t);
    r.message = settings_.mode == Mode::emission
                    ? "colour is outside the spectral locus of the grid; desaturated toward D65"
                    : "colour is outside the reflectance solid; desaturated toward the "
                      "reference white (and dimmed to Y <= 1)";
    // A move below float precision (e.g. white through OCIO's float maths landing a hair
    // outside the solid's white vertex) is rounding, not an out-of-gamut colour.
    if (relative_error(t, requested) <= kSnapTolerance) {
      r.status = Status::ok;
      r.message.clear();
    }
  }
  r.target = t;
  if (!(t.Y > 0)) {  // a non-zero colour of zero luminance maps to black: only black has Y = 0
    r.target = Xyz{};
    return r;
  }

  // The paper's average of admissible partial solutions, edge-filtered.
  PaperSpectrum paper = solver_.solve(t, settings_.filter);
  r.admissible = paper.admissible;
  r.dropped = paper.dropped;

  // Exact to double precision, non-negative, and <= 1 for reflectances: the closest such
  // spectrum to the paper's (a no-op polish unless the bound rho <= 1 is violated).
  const double upper = settings_.mode == Mode::reflectance ? 1.0 : INFINITY;
  const double peak =
      paper.values.empty() ? 0.0 : *std::max_element(paper.values.begin(), paper.values.end());
  r.bounded = settings_.mode == Mode::reflectance && peak > 1.0;
  Projection proj = project_exact(weights_.columns(), paper.values, t, upper);

  // Filter "auto": if even the ladder's last step leaves an edge peak (saturated colours that
  // need light near an end of the range), cap the edge bands below the interior mean by the
  // same exact projection, and keep the result only if it is peak-free.
  if (settings_.filter.kind() == EdgeFilter::Kind::automatic && proj.converged &&
      !solver_.free_of_edge_peaks(proj.values)) {
    std::vector<double> bounds = edge_caps(proj.values, upper);
    Projection capped = project_exact(weights_.columns(), proj.values, t, bounds);
    if (capped.converged && solver_.free_of_edge_peaks(capped.values)) {
      proj = std::move(capped);
      r.edge_capped = true;
    }
  }
  r.values = std::move(proj.values);
  r.xyz = weights_.integrate(r.values);
  r.relative_error = relative_error(r.xyz, t);
  if (!proj.converged && r.relative_error > 1e-9) {
    r.message += (r.message.empty() ? "" : "; ") +
                 std::string("the exact solver did not converge (relative error reported)");
  }
  return r;
}

}  // namespace spectralize
