#pragma once
// The two measurements the path tracer makes.
//
// Convergence: the scene under an HDRI, every RGB made spectral by spectralize::rt (the texture
// through a reflectance table, the HDRI through an emission table), four hero wavelengths per
// path, against the dense reference: the same paths with the spectra spectralize wrote for the
// same images (spectral EXRs) integrated over all 471 wavelengths of the 1 nm table. The
// difference is the wavelength sampling's noise, falling as 1/sqrt(spp), above a floor: rt's
// spectra integrated over all wavelengths against the files' (float exactness).
//
// Comparison: the ColorChecker chart under a light of one CIE illuminant's spectrum (its
// brightness following the HDRI's luminance), rendered with the measured reflectances (the
// truth), with spectralize::rt and with the Jakob & Hanika baseline, on shared paths and
// wavelengths.

#include <string>
#include <vector>

#include "path_tracer/image_difference.h"
#include "path_tracer/scene.h"
#include "spectralize/core/xyz.h"

namespace spectralize::path_tracer {

/// What every measurement shares.
struct RenderSettings {
  int size = 64;                    // square image, pixels
  std::vector<int> spp{4, 16, 64};  // sample counts to report (increasing)
  int threads = 2;
  std::string png_prefix;  // when set: PREFIX_<render>.png and difference maps
  SceneLayout layout;
};

struct ConvergenceSetup {
  std::string texture, texture_space = "sRGB - Texture";
  std::string environment, environment_space = "Linear Rec.709 (sRGB)";
  std::string reflectance_table, emission_table;     // spectralize table files
  std::string texture_spectra, environment_spectra;  // spectralize's spectral EXRs
  float light_scale = 1;                             // the HDRI's emission scale
  RenderSettings render;
};

struct ConvergencePoint {
  int spp = 0;
  DeltaEStats rt;  // hero-wavelength rt render against the dense reference, all pixels
};

struct ConvergenceReport {
  std::vector<ConvergencePoint> points;
  DeltaEStats floor;  // rt's spectra over all wavelengths against the reference, all pixels
  int floor_spp = 0;  // ... on this many paths per pixel
  double floor_relative_xyz = 0;  // max over pixels of |XYZ difference| / the white's Y
  long mapped = 0, invalid = 0;   // rt lookups whose colour was mapped into the gamut / invalid
  Xyz white;                      // CIELAB white: a white surface facing up
  double seconds = 0;
};

/// Renders the convergence scene (rt hero, rt over all wavelengths, the dense reference) and
/// measures. Throws Error naming a file that cannot be used. Cost: O(size^2 spp x 118 packets).
ConvergenceReport run_convergence(const ConvergenceSetup& setup);

struct ComparisonSetup {
  std::string texture, texture_space = "sRGB - Texture";                 // the ColorChecker chart
  std::string environment, environment_space = "Linear Rec.709 (sRGB)";  // luminance pattern
  std::string reflectance_table;  // of a model that has not seen the chart: not exemplar
  std::string illuminant = "A";   // the light's spectrum (any CIE illuminant name)
  int sigmoid_resolution = 64;    // the baseline's table (pbrt-v4's is 64)
  double map_scale = 5;           // dE2000 at the bright end of the maps
  RenderSettings render;
};

struct ComparisonReport {
  std::string illuminant;
  int spp = 0;
  DeltaEStats rt_vs_truth, baseline_vs_truth, rt_vs_baseline;  // pixels fully on surfaces
  long mapped = 0;  // rt lookups mapped into the gamut (the chart's clipped cyan: none)
  double sigmoid_max_node_delta_e76 = 0;  // the baseline table's worst node fit
  double seconds = 0;
};

/// Renders the comparison (truth, rt, baseline) at the last spp of `setup.render` and measures.
/// Throws Error naming a file that cannot be used. Cost: the baseline's table (3 res^3 fits)
/// + O(size^2 spp).
ComparisonReport run_comparison(const ComparisonSetup& setup);

/// The reports as JSON (for tests and documentation). Cost: O(points).
std::string to_json(const ConvergenceReport& report);
std::string to_json(const ComparisonReport& report);

}  // namespace spectralize::path_tracer
