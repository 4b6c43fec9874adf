#include "spectralize/core/spectralizer.h"

#include <algorithm>
#include <cmath>

#include "core/work_counts.h"
#include "spectralize/core/error.h"

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

// kLocusMargin, kSolidMargin (spectralizer.h): the fraction of the way back from the
// boundary keeps mapped targets strictly inside, where the fan of admissible triangles (locus)
// and the bounded projection (solid; its solutions near the boundary converge slowly, found by
// fuzzing) are well conditioned. kSnapTolerance: float input precision.

}  // namespace

std::string_view to_string(Mode mode) {
  return mode == Mode::emission ? "emission" : "reflectance";
}

Mode parse_mode(std::string_view text) {
  if (text == "emission") return Mode::emission;
  if (text == "reflectance") return Mode::reflectance;
  throw Error("unknown mode " + quote(text) + " (valid: emission, reflectance)");
}

std::string parse_emission_basis(std::string_view text) {
  std::string lower(text);
  for (char& ch : lower) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  if (lower == "flat") return "flat";
  try {
    return Illuminant::get(text).name;
  } catch (const Error& e) {
    throw Error("unknown emission basis " + quote(text) +
                " (valid: flat or an illuminant name, e.g. D65, A, FL2)");
  }
}

std::string_view to_string(Outcome outcome) {
  switch (outcome) {
    case Outcome::exact:
      return "ok";
    case Outcome::black:
      return "black";
    case Outcome::negative:
    case Outcome::outside_locus:
    case Outcome::outside_solid:
      return "out_of_gamut";
    case Outcome::invalid:
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
      locus_(ConvexGamut::spectral_locus(basis_columns_)),
      gamut_(settings_.mode == Mode::emission ? locus_
                                              : ConvexGamut::reflectance_solid(weights_.columns())),
      white_balance_{1, 1, 1} {
  count_work(Work::spectralizer_built);
  const std::vector<double> wavelengths = wavelengths_of(settings_.grid);
  ModelContext context{basis_columns_, wavelengths, settings_.grid.step(), settings_.filter,
                       settings_.curvature_nm};
  model_ = settings_.model.info().make(context);
  // Eq. 6: the white of the input (D65) becomes the white of the spectra: the reference
  // illuminant's perfect reflector, or, for emission with an illuminant basis, that
  // illuminant's light ("solved like a reflectance"; with D65 the change is ~1e-4, the
  // rounding of D65's xy in colour-space definitions).
  const bool basis = *std::min_element(basis_.begin(), basis_.end()) != 1.0 ||
                     *std::max_element(basis_.begin(), basis_.end()) != 1.0;
  if (settings_.mode == Mode::reflectance || basis)
    white_balance_ = balance_from_d65(settings_.mode == Mode::reflectance ? weights_.unit_white()
                                                                          : basis_white_);
}

Xyz Spectralizer::map_into_gamut(const Xyz& requested, SpectrumResult& r) const {
  const bool reflectance = settings_.mode == Mode::reflectance;
  if (gamut_.contains(requested)) return requested;
  r.status = Outcome::outside_solid;  // unless the first step below finds it outside the locus
  Xyz t = requested;
  std::string what;
  // Moves t toward `anchor` (inside) until it is inside `gamut`, a hair short of the boundary.
  auto move_toward = [&](const ConvexGamut& gamut, const Xyz& anchor) {
    if (gamut.contains(t)) return;
    const double margin = &gamut == &locus_ ? kLocusMargin : kSolidMargin;
    // `margin` of the way short of the boundary (the fraction of the segment that the solvers
    // were fuzzed with); for colours so far outside that the boundary lies within 2 margins of
    // the anchor (an 8-bit 255 read as 0..1), half way to it instead, so they keep their
    // chromaticity rather than landing on the anchor. The rules agree at the switch.
    const double sb = gamut.max_step(anchor, t);
    const double s = sb >= 2 * margin ? sb - margin : 0.5 * sb;
    t = anchor + s * (t - anchor);
  };
  // 1. Chromaticity outside the spectral locus: toward the white at the same luminance. The
  //    white is D65 (reflectance: the reference white), or if a narrow grid cannot make D65,
  //    the colour of the flat spectrum, which every grid can.
  if (!locus_.contains(t)) {
    r.status = Outcome::outside_locus;
    const Xyz white = mapping_white();
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
    r.status = Outcome::exact;
    r.message.clear();
  }
  return t;
}

Xyz Spectralizer::mapping_white() const {
  const Xyz white = settings_.mode == Mode::reflectance ? weights_.unit_white() : kWhiteD65;
  return locus_.contains(white) ? white : basis_white_;
}

Xyz Spectralizer::mapped_target(const Xyz& target, Outcome& outcome) const {
  SpectrumResult r;
  const Xyz t = map_into_gamut(target, r);
  outcome = r.status;
  return t;
}

Xyz Spectralizer::target_of(const Xyz& xyz_d65) const {
  return hadamard(xyz_d65, white_balance_);
}

SpectrumResult Spectralizer::spectralize(const Xyz& xyz_d65) const {
  if (!xyz_d65.finite()) {  // reject what no spectrum can mean
    SpectrumResult r;
    r.values.assign(settings_.grid.size(), 0.0);
    r.input = xyz_d65;
    r.status = Outcome::invalid;
    r.message = "colour has NaN or infinite components";
    return r;
  }
  SpectrumResult r = spectralize_target(target_of(xyz_d65));
  r.input = xyz_d65;
  return r;
}

SpectrumResult Spectralizer::classify(const Xyz& xyz_d65) const {
  SpectrumResult r;
  r.values.assign(settings_.grid.size(), 0.0);
  r.input = xyz_d65;
  if (!xyz_d65.finite()) {
    r.status = Outcome::invalid;
    r.message = "colour has NaN or infinite components";
    return r;
  }
  const Xyz t = target_of(xyz_d65);
  if (t == Xyz{}) {
    r.status = Outcome::black;
    return r;
  }
  if (t.Y < 0) {
    r.status = Outcome::negative;
    r.message = "colour has negative luminance (Y < 0): mapped to black";
    return r;
  }
  r.target = map_into_gamut(t, r);
  if (!(r.target.Y > 0)) r.target = Xyz{};  // a colour of zero luminance maps to black
  return r;
}

SpectrumResult Spectralizer::spectralize_target(const Xyz& target) const {
  SpectrumResult r;
  const std::size_t n = settings_.grid.size();
  r.values.assign(n, 0.0);
  r.input = target;
  if (!target.finite()) {
    r.status = Outcome::invalid;
    r.message = "colour has NaN or infinite components";
    return r;
  }
  Xyz t = target;
  if (t == Xyz{}) {
    r.status = Outcome::black;
    return r;
  }
  if (t.Y < 0) {
    r.status = Outcome::negative;
    r.message = "colour has negative luminance (Y < 0): mapped to black";
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
    r.status = Outcome::exact;
    r.message.clear();
    return r;
  }

  const double upper = settings_.mode == Mode::reflectance ? 1.0 : INFINITY;
  ModelSolution solution = model_->solve(t, upper);
  // Back from s to the spectrum (a no-op for reflectances and flat emission); the bounds hold
  // bit-exactly (a solver's last rounding may step a hair outside).
  r.values = std::move(solution.values);
  for (std::size_t i = 0; i < n; ++i) r.values[i] = std::clamp(r.values[i], 0.0, upper) * basis_[i];
  r.fallback = solution.fallback;
  r.details = std::move(solution.details);
  r.xyz = weights_.integrate(r.values);
  r.relative_error = relative_error(r.xyz, t);
  if (!solution.converged && !(r.relative_error <= 1e-9)) {
    r.message += (r.message.empty() ? "" : "; ") +
                 std::string("the exact solver did not converge (relative error reported)");
  }
  return r;
}

}  // namespace spectralize
