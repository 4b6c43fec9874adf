#pragma once
// The exact spectralizer: input XYZ (D65-adapted) -> a spectrum on a wavelength grid whose XYZ
// under the reference integration is the (gamut-mapped) input, non-negative, and <= 1 for
// reflectances. Does what every model shares (white balance, gamut mapping, emission basis)
// around the chosen spectrum model (docs/DESIGN.md §6).

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "spectralize/core/colorimetry.h"
#include "spectralize/core/edge_filter.h"
#include "spectralize/core/gamut.h"
#include "spectralize/core/sample_weights.h"
#include "spectralize/core/spectrum_model.h"
#include "spectralize/core/wavelength_grid.h"
#include "spectralize/core/xyz.h"

namespace spectralize {

enum class Mode { emission, reflectance };

/// "emission" / "reflectance". Cost: O(1).
std::string_view to_string(Mode mode);
/// Parses "emission" | "reflectance"; throws Error. Cost: O(1).
Mode parse_mode(std::string_view text);

/// The smooth model's default curvature length tau (chosen by measurement; see
/// docs/guide/conventions.md).
inline constexpr double kDefaultCurvatureNm = 50;

/// Canonical emission basis: "flat" (any case) or an illuminant's canonical name; throws Error
/// naming the valid values. Cost: O(table) for an illuminant.
std::string parse_emission_basis(std::string_view text);

/// What became of a colour: the one outcome of a --color value, an array's colour and a pixel
/// alike (docs/DESIGN.md §5), counted per kind for images and arrays.
enum class Outcome : std::uint8_t {
  exact,          // exact spectrum of the colour
  black,          // zero colour: zero spectrum
  invalid,        // NaN or infinite: no colour at all; zero spectrum
  negative,       // negative luminance (Y < 0): no light or surface has it; out of gamut,
                  // mapped to black (zero spectrum)
  outside_locus,  // outside the spectral locus: mapped (docs/DESIGN.md §5), then exact
  outside_solid,  // reflectance outside the reflectance solid: mapped, then exact
};

/// True for the outcomes of a colour mapped into the gamut first (negative luminance, outside
/// the locus or the solid): out of gamut, a warning, not a failure. Cost: O(1).
constexpr bool out_of_gamut(Outcome outcome) {
  return outcome == Outcome::negative || outcome == Outcome::outside_locus ||
         outcome == Outcome::outside_solid;
}

/// The status reports give: "ok" (exact), "black", "out_of_gamut" (any mapped outcome) or
/// "invalid". Cost: O(1).
std::string_view to_string(Outcome outcome);

/// The white point of every space in the shipped OCIO config: D65, Y = 1.
inline constexpr Xyz kWhiteD65{0.3127 / 0.3290, 1.0, 0.3583 / 0.3290};

/// The diagonal white balance that takes the D65 white to `white` (docs/DESIGN.md §3: XYZ
/// scaling, not a Bradford adaptation); its inverse is balance_from_d65(w) with the roles
/// swapped, i.e. hadamard(xyz, d65_from(w)). Cost: O(1).
inline Xyz balance_from_d65(const Xyz& white) {
  return {white.X / kWhiteD65.X, white.Y / kWhiteD65.Y, white.Z / kWhiteD65.Z};
}
/// The diagonal that takes `white` back to the D65 white (the inverse of balance_from_d65).
/// Cost: O(1).
inline Xyz balance_to_d65(const Xyz& white) {
  return {kWhiteD65.X / white.X, kWhiteD65.Y / white.Y, kWhiteD65.Z / white.Z};
}

/// Gamut mapping (docs/DESIGN.md §5): mapped targets stop this fraction of the segment short
/// of the spectral locus / the reflectance solid; a move below kSnapTolerance (relative XYZ)
/// is rounding, not out of gamut.
inline constexpr double kLocusMargin = 1e-6;
inline constexpr double kSolidMargin = 1e-4;
inline constexpr double kSnapTolerance = 1e-6;

/// The edge filter used when none is given (chosen by measurement; see the guide's "Edge filter"
/// (docs/guide/conventions.md)).
EdgeFilter default_edge_filter();

struct SpectralizerSettings {
  WavelengthGrid grid;               // default 380:780:5
  std::string observer = "cie1931";  // cie1931 | cie1964
  Mode mode = Mode::emission;
  std::string illuminant = "D65";             // reference illuminant of reflectances
  EdgeFilter filter = default_edge_filter();  // paper model only
  RegisteredModel model;                      // default_model_name() unless chosen
  // Emission only: "flat" (phi >= 0 free per sample) or an illuminant name, e.g. "D65": the
  // spectrum is E(lambda) s(lambda) with s >= 0, and the input white (D65) is balanced to E's
  // colour like a reflectance's (eq. 6), so white light becomes E itself.
  std::string emission_basis = "flat";
  // Smooth model only: tau in the roughness integral of x'^2 + tau^2 x''^2 (nm); 0 = slope only.
  double curvature_nm = kDefaultCurvatureNm;
};

struct SpectrumResult {
  std::vector<double> values;  // one per grid sample
  Outcome status = Outcome::exact;
  Xyz input;                         // the XYZ given (D65-adapted, input units)
  Xyz target;                        // what the spectrum reproduces: input (emission) or input
                                     // white-balanced to the reference illuminant (reflectance),
                                     // after gamut mapping
  Xyz xyz;                           // W . values: the reference integration of the spectrum
  double relative_error = 0;         // max|xyz - target| / max|target|
  bool fallback = false;             // the model's stated fallback produced (part of) the spectrum
  std::vector<ModelDetail> details;  // the model's own diagnostics (e.g. paper: L and K)
  double gamut_distance = 0;         // chromaticity (xy) distance the mapping moved the colour
  std::string message;               // why the status is not ok, for people

  /// The model's detail `name` (e.g. "admissible"), 0 when the model does not report it.
  /// Cost: O(details).
  double detail(std::string_view name) const {
    for (const ModelDetail& d : details)
      if (d.name == name) return d.value;
    return 0;
  }
};

class Spectralizer {
 public:
  /// Builds weights, solver and gamut for the settings; throws Error for unknown observers or
  /// illuminants. Cost: O(N^3) (the gamut facets), ~1 ms at 5 nm.
  explicit Spectralizer(SpectralizerSettings settings);

  /// The spectrum of a colour given as CIE XYZ (D65-adapted, e.g. OCIO's CIE-XYZ-D65). Never
  /// throws; problems are in the status. Thread-safe. Cost: ~O(N^2 + L), tens of us at 5 nm.
  SpectrumResult spectralize(const Xyz& xyz_d65) const;

  /// What spectralize() says about a colour without its spectrum: status, input, target (gamut
  /// mapped), message, gamut distance; values all zero (for a table's spectrum of the colour).
  /// Never throws. Cost: O(facets).
  SpectrumResult classify(const Xyz& xyz_d65) const;

  /// As spectralize(), for a target already in the mode's terms (reflectance: white
  /// balanced, see target_of). Never throws. Thread-safe. Cost: as spectralize().
  SpectrumResult spectralize_target(const Xyz& target) const;

  /// The target the spectrum must reproduce, before gamut mapping (reflectance: white
  /// balanced). Cost: O(1).
  Xyz target_of(const Xyz& xyz_d65) const;
  /// True when the target is inside the gamut of the mode. Cost: O(facets).
  bool in_gamut(const Xyz& target) const { return gamut_.contains(target); }
  /// What (1, 1, 1) of a D65 space becomes as a target: W_ref (reflectance) or D65. Cost: O(1).
  Xyz reference_white() const { return hadamard(kWhiteD65, white_balance_); }
  /// The diagonal from a spectrum's XYZ back to the input's D65 terms (the inverse of the
  /// white balance; 1 for flat emission). Cost: O(1).
  Xyz unbalance() const { return balance_to_d65(reference_white()); }

  /// The gamut of the mode (emission: the locus; reflectance: the solid) and the spectral
  /// locus, as the mapping uses them. Cost: O(1).
  const ConvexGamut& gamut() const { return gamut_; }
  const ConvexGamut& locus() const { return locus_; }
  /// The white a colour outside the locus is desaturated toward, per unit Y times its Y
  /// (reflectance: the reference white; emission: D65, or the basis' white when a narrow grid
  /// cannot make D65). Cost: O(facets).
  Xyz mapping_white() const;
  /// The target a colour is mapped to (docs/DESIGN.md §5), with `outcome` exact (not moved by
  /// more than rounding: returned as is), outside_locus or outside_solid. Never throws.
  /// Cost: O(facets).
  Xyz mapped_target(const Xyz& target, Outcome& outcome) const;

  const SpectralizerSettings& settings() const { return settings_; }
  const SampleWeights& weights() const { return weights_; }
  /// The emission basis on the grid (all 1 unless an illuminant basis). Cost: O(1).
  const std::vector<double>& basis() const { return basis_; }
  const Observer& observer() const { return *observer_; }
  /// The reference illuminant (reflectance mode) or nullptr (emission). Cost: O(1).
  const Illuminant* illuminant() const { return illuminant_.get(); }

 private:
  /// Moves an out-of-gamut target inside and records status, distance and message in `r`:
  /// outside the locus toward white at constant Y; reflectance with Y > 1 toward black (keeps the
  /// chromaticity); still outside the solid toward white at constant Y. Cost: O(facets).
  Xyz map_into_gamut(const Xyz& target, SpectrumResult& r) const;
  SpectralizerSettings settings_;
  const Observer* observer_;
  std::unique_ptr<Illuminant> illuminant_;
  SampleWeights weights_;
  // The solvers work on s with spectrum = basis * s: basis 1 (reflectance, flat emission) or
  // an illuminant scaled to Y = 1; their weights are the columns scaled by the basis.
  std::vector<double> basis_;
  std::vector<Xyz> basis_columns_;
  Xyz basis_white_;  // W . basis: the colour of s == 1
  std::unique_ptr<SpectrumModel> model_;
  ConvexGamut locus_;  // the cone of the weights: chromaticities any spectrum can have
  ConvexGamut gamut_;  // emission: the locus; reflectance: the solid
  Xyz white_balance_;  // W_ref / W_D65 per component (reflectance), else (1, 1, 1)
};

}  // namespace spectralize
