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

// The emission basis on the grid: 1 (flat; any reflectance) or the illuminant, linearly
// interpolated on its 1 nm table and scaled so that basis * 1 has Y = 1.
std::vector<double> basis_of(const SpectralizerSettings& s, const SampleWeights& weights) {
  std::vector<double> basis(s.grid.size(), 1.0);
  const std::string name = parse_emission_basis(s.emission_basis);  // throws for unknown names
  if (name == "flat") return basis;
  const Illuminant il = Illuminant::get(name);
  if (s.mode != Mode::emission) return basis;
  double y = 0;
  for (std::size_t i = 0; i < basis.size(); ++i) {
    const double pos = std::clamp(s.grid[i] - ReferenceTable::kStartNm, 0.0,
                                  static_cast<double>(ReferenceTable::kSize - 1));
    const std::size_t k = std::min(static_cast<std::size_t>(pos), ReferenceTable::kSize - 2);
    const double f = pos - static_cast<double>(k);
    basis[i] = std::max(0.0, (1 - f) * il.spd[k] + f * il.spd[k + 1]);
    y += basis[i] * weights.columns()[i].Y;
  }
  if (!(y > 0)) throw Error("emission basis '" + s.emission_basis + "' has no light on the grid");
  for (double& b : basis) b /= y;
  return basis;
}

std::vector<Xyz> scaled_columns(const SampleWeights& weights, const std::vector<double>& basis) {
  std::vector<Xyz> columns = weights.columns();
  for (std::size_t i = 0; i < columns.size(); ++i) columns[i] = basis[i] * columns[i];
  return columns;
}

double chromaticity_distance(const Xyz& a, const Xyz& b) {
  double sa = a.sum(), sb = b.sum();
  if (!(sa > 0) || !(sb > 0)) return 0;
  return std::hypot(a.X / sa - b.X / sb, a.Y / sa - b.Y / sb);
}

// Fraction of the way back from the boundary: keeps mapped targets strictly inside, where the
// fan of admissible triangles (locus) and the bounded projection (solid; its solutions near
// the boundary converge slowly, found by fuzzing) are well conditioned.
constexpr double kLocusMargin = 1e-6;
constexpr double kSolidMargin = 1e-4;

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

std::string_view to_string(Model model) {
  return model == Model::paper ? "paper" : "smooth";
}

Model parse_model(std::string_view text) {
  if (text == "paper") return Model::paper;
  if (text == "smooth") return Model::smooth;
  throw Error("unknown model '" + std::string(text) + "' (valid: paper, smooth)");
}

std::string parse_emission_basis(std::string_view text) {
  std::string lower(text);
  for (char& ch : lower) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  if (lower == "flat") return "flat";
  try {
    return Illuminant::get(text).name;
  } catch (const Error& e) {
    throw Error("unknown emission basis '" + std::string(text) +
                "' (valid: flat or an illuminant name, e.g. D65, A, FL2)");
  }
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
      basis_(basis_of(settings_, weights_)),
      basis_columns_(scaled_columns(weights_, basis_)),
      basis_white_(weights_.integrate(basis_)),
      solver_(basis_columns_, wavelengths_of(settings_.grid)),
      locus_(ConvexGamut::spectral_locus(basis_columns_)),
      gamut_(settings_.mode == Mode::emission ? locus_
                                              : ConvexGamut::reflectance_solid(weights_.columns())),
      white_balance_{1, 1, 1} {
  if (settings_.model == Model::smooth)
    smooth_ = std::make_unique<SmoothSolver>(
        basis_columns_, Roughness::of_length(settings_.curvature_nm, settings_.grid.step()));
  // Eq. 6: the white of the input (D65) becomes the white of the spectra: the reference
  // illuminant's perfect reflector, or, for emission with an illuminant basis, that
  // illuminant's light ("solved like a reflectance"; with D65 the change is ~1e-4, the
  // rounding of D65's xy in colour-space definitions).
  const bool basis = *std::min_element(basis_.begin(), basis_.end()) != 1.0 ||
                     *std::max_element(basis_.begin(), basis_.end()) != 1.0;
  if (settings_.mode == Mode::reflectance || basis) {
    const Xyz ref = settings_.mode == Mode::reflectance ? weights_.unit_white() : basis_white_;
    white_balance_ = {ref.X / kWhiteD65.X, ref.Y / kWhiteD65.Y, ref.Z / kWhiteD65.Z};
  }
}

Xyz Spectralizer::map_into_gamut(const Xyz& requested, SpectrumResult& r) const {
  const bool reflectance = settings_.mode == Mode::reflectance;
  if (gamut_.contains(requested)) return requested;
  r.status = Status::out_of_gamut;
  Xyz t = requested;
  std::string what;
  // Moves t toward `anchor` (inside) until it is inside `gamut`, a hair short of the boundary.
  auto move_toward = [&](const ConvexGamut& gamut, const Xyz& anchor) {
    if (gamut.contains(t)) return;
    const double margin = &gamut == &locus_ ? kLocusMargin : kSolidMargin;
    double s = std::max(0.0, gamut.max_step(anchor, t) - margin);
    t = anchor + s * (t - anchor);
  };
  // 1. Chromaticity outside the spectral locus: toward the white at the same luminance. The
  //    white is D65 (reflectance: the reference white), or if a narrow grid cannot make D65,
  //    the colour of the flat spectrum, which every grid can.
  if (!locus_.contains(t)) {
    r.outside_locus = true;
    Xyz white = reflectance ? weights_.unit_white() : kWhiteD65;
    if (!locus_.contains(white)) white = basis_white_;
    move_toward(locus_, (t.Y / white.Y) * white);
    what = "outside the spectral locus: desaturated toward white at constant luminance";
  }
  if (reflectance && !gamut_.contains(t)) {
    // 2. Brighter than any reflectance of its chromaticity and Y > 1: dimmed toward black,
    //    which keeps the hue (a bright red stays red rather than turning white).
    if (t.Y > 1) {
      move_toward(gamut_, Xyz{});
      what += std::string(what.empty() ? "" : "; ") +
              "brighter than any reflectance (Y > 1): dimmed at constant chromaticity";
    }
    // 3. Too saturated for a reflectance of its luminance: toward white at constant Y.
    if (!gamut_.contains(t)) {
      move_toward(gamut_, t.Y * weights_.unit_white());
      what += std::string(what.empty() ? "" : "; ") +
              "outside the reflectance solid: desaturated toward the reference white at "
              "constant luminance";
    }
  }
  r.gamut_distance = chromaticity_distance(requested, t);
  r.message = "colour is " + what;
  if (requested.Y > 0 && !(t.Y > 0)) r.message = "colour has zero luminance: mapped to black";
  if (requested.Y == 0) r.message = "colour is not black but has zero luminance: mapped to black";
  // A move below float precision (e.g. white through OCIO's float maths landing a hair
  // outside the solid's white vertex) is rounding, not an out-of-gamut colour.
  if (relative_error(t, requested) <= kSnapTolerance) {
    r.status = Status::ok;
    r.message.clear();
  }
  return t;
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
  if (!xyz_d65.finite()) {  // reject what no spectrum can mean
    SpectrumResult r;
    r.values.assign(settings_.grid.size(), 0.0);
    r.input = xyz_d65;
    r.status = Status::invalid;
    r.message = "colour has NaN or infinite components";
    return r;
  }
  SpectrumResult r = spectralize_target(target_of(xyz_d65));
  r.input = xyz_d65;
  return r;
}

SpectrumResult Spectralizer::spectralize_target(const Xyz& target) const {
  SpectrumResult r;
  const std::size_t n = settings_.grid.size();
  r.values.assign(n, 0.0);
  r.input = target;
  if (!target.finite()) {
    r.status = Status::invalid;
    r.message = "colour has NaN or infinite components";
    return r;
  }
  Xyz t = target;
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

  // Map out-of-gamut colours into the gamut (see map_into_gamut for the rule).
  const Xyz requested = t;
  t = map_into_gamut(t, r);
  r.target = t;
  if (!(t.Y > 0)) {  // only black has Y = 0: a non-zero colour of zero luminance maps to it
    r.target = Xyz{};
    return r;
  }

  // The colour of s == 1 (reflectance: white, the perfect reflector; emission: the flat
  // spectrum or the basis illuminant), within float precision, is exactly that spectrum
  // scaled: near it the solvers pin XYZ but not the samples the eye barely sees.
  const double white_scale = settings_.mode == Mode::reflectance ? 1.0 : requested.Y;
  if (relative_error(requested, white_scale * basis_white_) <= kSnapTolerance) {
    for (std::size_t i = 0; i < n; ++i) r.values[i] = white_scale * basis_[i];
    r.target = white_scale * basis_white_;
    r.xyz = weights_.integrate(r.values);
    r.relative_error = relative_error(r.xyz, r.target);
    r.status = Status::ok;
    r.message.clear();
    return r;
  }

  const double upper = settings_.mode == Mode::reflectance ? 1.0 : INFINITY;
  Projection proj = smooth_ ? solve_smooth(t, upper) : solve_paper(t, upper, r);
  // Back from s to the spectrum (a no-op for reflectances and flat emission).
  r.values = std::move(proj.values);
  for (std::size_t i = 0; i < n; ++i) r.values[i] *= basis_[i];
  r.xyz = weights_.integrate(r.values);
  r.relative_error = relative_error(r.xyz, t);
  if (!proj.converged && !(r.relative_error <= 1e-9)) {
    r.message += (r.message.empty() ? "" : "; ") +
                 std::string("the exact solver did not converge (relative error reported)");
  }
  return r;
}

Projection Spectralizer::solve_paper(const Xyz& t, double upper, SpectrumResult& r) const {
  // The paper's average of admissible partial solutions, edge-filtered.
  PaperSpectrum paper = solver_.solve(t, settings_.filter);
  r.admissible = paper.admissible;
  r.dropped = paper.dropped;

  // Exact to double precision: the paper's average is exact in exact arithmetic, so a tiny
  // relative polish suffices. If that fails, or a reflectance exceeds 1, the fallback is the
  // closest spectrum that is exact, non-negative and <= 1 (bounded projection).
  Projection proj;
  proj.values = paper.values;
  proj.converged = polish_exact(basis_columns_, proj.values, t);
  const double peak = *std::max_element(proj.values.begin(), proj.values.end());
  r.bounded = settings_.mode == Mode::reflectance && peak > 1.0;
  if (!proj.converged || peak > upper) proj = project_exact(basis_columns_, paper.values, t, upper);

  // Filter "auto": if even the ladder's last step leaves an edge peak (saturated colours that
  // need light near an end of the range), cap the edge bands below the interior mean by the
  // same exact projection, and keep the result only if it is peak-free.
  if (settings_.filter.kind() == EdgeFilter::Kind::automatic && proj.converged &&
      !solver_.free_of_edge_peaks(proj.values)) {
    std::vector<double> bounds = edge_caps(proj.values, upper);
    Projection capped = project_exact(basis_columns_, proj.values, t, bounds);
    if (capped.converged && solver_.free_of_edge_peaks(capped.values)) {
      proj = std::move(capped);
      r.edge_capped = true;
    }
  }
  return proj;
}

Projection Spectralizer::solve_smooth(const Xyz& t, double upper) const {
  SmoothSpectrum smooth = smooth_->solve(t, upper);
  if (!smooth.converged) {
    // Rare: targets hugging the gamut boundary (the mapping leaves them 1e-6 inside the locus),
    // where the fast phase cycles and the solver's own projection to a feasible start stalls.
    // The paper model's spectrum is within the bounds and exact (or within 1e-6 of it, for
    // the dark purples where its projection stalls; the primal phase's first full step makes
    // it exact): start the primal phase there.
    SpectrumResult scratch;
    const Projection paper = solve_paper(t, upper, scratch);
    Xyz xyz;
    for (std::size_t i = 0; i < paper.values.size(); ++i)
      xyz = xyz + paper.values[i] * basis_columns_[i];
    if (paper.converged || relative_error(xyz, t) <= 1e-6)
      smooth = smooth_->solve(t, upper, paper.values);
  }
  Projection proj;
  proj.values = std::move(smooth.values);
  proj.converged = smooth.converged;
  proj.iterations = smooth.iterations;
  return proj;
}

}  // namespace spectralize
