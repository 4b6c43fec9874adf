#pragma once
// `spectralize_figures validate OUTDIR`: how the reconstructed spectra compare with measured
// ones. Each set of measured reflectances (the 24 ColorChecker patches of Ohta, the 190 AMPAS
// rawtoaces training patches) is turned into colours under D65 in a working space, reconstructed
// by every row (the registered models, and reference lines that are not models: what data alone
// achieves, rgb2spec) and compared with the measurement under D65 (the round trip) and under six
// other lights (metamerism), spectrally (RMSE) and in roughness; CIE illuminants A, D50 and FL2
// given as RGB are spectralized as lights by every model and compared with their real SPDs.
// Each row is one entry of validation_configs(): adding a row is adding an entry there.

#include <array>
#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "colour/colour_space.h"
#include "spectralize/core/edge_filter.h"
#include "spectralize/core/spectralizer.h"

namespace spectralize::figures {

/// The lights reflectances are compared under besides D65 (the round trip): CIE A, FL11, FL2,
/// LED-B3, HP1 and D50 (docs/MODEL_STUDY.md). Cost: O(1).
std::vector<std::string> validation_lights();

/// A measured reflectance on the grid (the stored samples interpolated linearly).
struct MeasuredPatch {
  std::string name;
  std::vector<double> rho;
};

/// What a row's reconstruction may use, for one working space.
struct RowContext {
  std::string space;
  const ColourTransform* to_xyz = nullptr;  // the space's linear RGB -> CIE XYZ (D65)
  const Spectralizer* protocol = nullptr;   // reflectance, default settings: targets, weights
  const std::vector<std::vector<MeasuredPatch>>* sets = nullptr;  // as validation_sets()
};

/// One patch's reflectance from a row.
struct Reconstructed {
  std::vector<double> values;  // on the grid
  std::string status;          // the spectralizer's status, or "ok" / "not_converged"
};

/// A row's way of turning a patch's colour into a reflectance: a registered model through the
/// Spectralizer, or a reference line.
class Reconstruction {
 public:
  virtual ~Reconstruction() = default;
  /// The reflectance of patch `patch` of set `set` (indices as validation_sets()), given as its
  /// colour `rgb` in the space (clipped to [0, 1]) and `xyz_d65`, the same colour in CIE XYZ
  /// (D65). The patch's own measurement must not be used (reference lines that learn from the
  /// sets leave it out). Cost: the method's.
  virtual Reconstructed reconstruct(std::size_t set, std::size_t patch,
                                    const std::array<double, 3>& rgb, const Xyz& xyz_d65) const = 0;
};

/// One way of reconstructing reflectances: a row of the summary tables.
struct ValidationConfig {
  std::string name;   // e.g. "paper, filter auto (default)"
  std::string model;  // the registered model (its lights are validated too); "" for a reference
  EdgeFilter filter;  // the paper model's
  bool exact = true;  // reproduces the D65 colour of every patch (the tests hold it to that)
  std::function<std::unique_ptr<Reconstruction>(const RowContext&)> make;
};

/// The rows: the paper model with the default filter and two fixed ones, the smooth and the
/// natural model (the default model's row says "(default)"), the natural model through the
/// render-time table (docs/DESIGN.md §14), the exemplar model, then the reference lines
/// (reference_rows.h). Cost: O(1).
std::vector<ValidationConfig> validation_configs();

/// The working spaces the colours are given in. Cost: O(1).
std::vector<std::string> validation_spaces();

/// A set of measured reflectances: the columns of an embedded data file.
struct PatchSet {
  std::string name;  // "ColorChecker", "AMPAS 190"
  std::string file;  // in data/
  std::size_t count = 0;
};

/// The measured sets, ColorChecker first. Cost: O(1).
std::vector<PatchSet> validation_sets();

/// One ColorChecker patch, measured spectrum against reconstruction.
struct PatchResult {
  std::string name;
  std::array<double, 3> rgb{};      // the patch's colour in the space (after clipping)
  bool clipped = false;             // outside [0, 1] in the space: clipped as a texture would
  std::string status;               // the spectralizer's status
  double delta_e_d65 = 0;           // round trip: spectrum vs the input colour, under D65
  double delta_e_d65_measured = 0;  // spectrum vs measurement under D65 (differs if clipped)
  std::vector<double> delta_e;      // spectrum vs measurement under each validation_lights()
  double rmse = 0;                  // RMS of reconstruction - measurement over the grid
  double roughness = 0;             // RMS of second differences of the reconstruction
  double roughness_measured = 0;    // ... of the measurement
  double edge_ratio = 0;            // edge_ratio() of the reconstruction
  double edge_ratio_measured = 0;   // ... of the measurement
  double relative_xyz_error = 0;    // |XYZ(spectrum) - target| / |target| (max norm)
  double rho_min = 0, rho_max = 0;
};

/// One CIE illuminant given as RGB and spectralized as a light (all normalised to Y = 1).
struct LightResult {
  std::string name;
  std::array<double, 3> rgb{};
  bool in_gamut = true;  // all RGB components >= 0 in the space
  std::string status;
  double delta_e_light = 0;   // the light's own colour, reconstruction vs real
  double rmse = 0;            // RMS spectral difference, reconstruction vs real SPD
  double roughness = 0;       // RMS of second differences of the reconstruction
  double roughness_real = 0;  // ... of the real SPD on the grid
  double edge_ratio = 0;      // edge_ratio() of the reconstruction
  double relative_xyz_error = 0;
  double checker_delta_e_median = 0;  // ColorChecker lit by the reconstruction vs the real
  double checker_delta_e_max = 0;     // light (measured reflectances, CIEDE2000)
};

/// Median, 95th percentile (linear interpolation) and maximum.
struct Spread {
  double median = 0, p95 = 0, max = 0;
};

struct ValidationSummary {
  Spread delta_e_d65;
  std::vector<Spread> delta_e;  // under each validation_lights()
  double mean_rmse = 0, mean_roughness = 0, mean_roughness_measured = 0;
  double max_relative_xyz_error = 0;
  double max_edge_ratio = 0, max_edge_ratio_measured = 0;
  double rho_min = 0, rho_max = 0;
  std::size_t clipped = 0;  // patches outside the space's [0, 1] cube
};

/// One measured set under one configuration and space.
struct PatchSetResult {
  PatchSet set;
  std::vector<PatchResult> patches;
  ValidationSummary summary;
};

/// Everything measured for one configuration in one space.
struct ConfigResult {
  ValidationConfig config;
  std::string space;
  bool available = true;  // false: the configuration threw (error says why)
  std::string error;
  std::vector<PatchSetResult> sets;  // as validation_sets()
  std::vector<LightResult> lights;
  double seconds = 0;
};

/// The baseline: an RGB renderer, which shows a patch under a light as the patch's RGB times
/// the light's RGB (the light's colour in the space), against the measured spectrum under that
/// light. Independent of the configuration; one per space.
struct RgbBaseline {
  std::string space, set;
  std::vector<std::string> patches;
  std::vector<std::vector<double>> delta_e;  // [light][patch], lights as validation_lights()
  std::vector<Spread> spreads;               // per light
};

/// Everything validate() measured.
struct Validation {
  std::vector<ConfigResult> configs;
  std::vector<RgbBaseline> baselines;
};

/// Median / p95 / max of `values` (empty: zeros). Cost: O(n log n).
Spread spread(std::vector<double> values);

/// RMS of the second differences x[i-1] - 2 x[i] + x[i+1]. Cost: O(N).
double roughness(const std::vector<double>& x);

/// The edge-peak figure of the guide's filter study: the largest sample within 20 nm of
/// either end of the grid over the mean of the samples in 400..700 nm. Cost: O(N).
double edge_ratio(const WavelengthGrid& grid, const std::vector<double>& x);

/// The measured sets on the default grid, as validation_sets(). Throws Error for missing or
/// malformed data. Cost: O(patches x N).
std::vector<std::vector<MeasuredPatch>> load_validation_sets();

/// Runs every configuration in every space on every set, and the RGB baseline. Configurations that
/// throw are kept, marked unavailable. Throws Error only for missing data or an unknown space.
/// Cost: ~0.05 s per configuration and space.
Validation validate(const ColourSpaces& spaces);

/// validate(), then writes OUTDIR/validation.json and OUTDIR/validation.md (temporary
/// files, renamed) and prints the summary to `out`. Throws Error naming the file and the
/// reason. Cost: validate() + ms.
void run_validation(const std::string& outdir, std::ostream& out);

}  // namespace spectralize::figures
