#pragma once
// The exemplar model (docs/DESIGN.md §6, chosen by the study of docs/MODEL_STUDY.md): the natural
// spectrum, except near the colours of measured materials (the development sets' reflectances:
// the 24 ColorChecker patches and the 190 AMPAS rawtoaces patches in data/), where it takes
// their measured shapes, made exact:
//
//   x = P_t((c x_natural + sum_j w_j rho_j) / (c + sum_j w_j)),   w_j = (1 - (d_j / h)^2)^3
//
// for d_j < h (else 0), d_j the distance of the target's colour from exemplar j's in CIEDE2000's
// metric at the exemplar (continuous, unlike CIEDE2000 itself), P_t the exact bounded
// least-squares projection (docs/DESIGN.md §5); x = x_natural where no exemplar is within h.
// Exact and bounded (a projection onto the exact bounded spectra), continuous in the colour (the
// weights vanish smoothly at h, and P_t(x_natural) = x_natural), natural's fallback near the
// gamut boundary, natural's spectra for lights.

#include <span>
#include <vector>

#include "core/colorimetry/colour_difference.h"
#include "core/solvers/natural_solver.h"
#include "spectralize/core/spectrum_model.h"

namespace spectralize {

class ExemplarModel final : public SpectrumModel {
 public:
  /// h: the radius of an exemplar's influence, in CIEDE2000 units (picked by the study).
  static constexpr double kRadius = 2.0;
  /// c: the natural spectrum's weight against an exemplar at distance 0 (picked by the study).
  static constexpr double kNaturalWeight = 0.1;

  /// The exemplars of both development sets (development_reflectances()). Cost: O(N^3) once
  /// (the natural solver's facets, ~1 ms at 5 nm) plus O(exemplars x N).
  explicit ExemplarModel(const ModelContext& context);
  /// The given exemplars (reflectances on the context's grid; clamped to [0, 1]): the
  /// validation's cross-validation scores one set with the other as the library. Cost: as above.
  ExemplarModel(const ModelContext& context, std::vector<std::vector<double>> exemplars);

  /// The blended spectrum; details: iterations, fallback_weight and safety_net (the natural
  /// solve's), exemplars (how many are within h), exemplar_weight (sum w / (c + sum w): 0 is
  /// the natural spectrum), projection_failed (the projection did not converge and the natural
  /// spectrum was kept: not continuous; not seen on any colour tested). Thread-safe.
  /// Cost: the natural solve plus ~1 us for the distances (214 exemplars) and, within h of an
  /// exemplar, one projection (~3 us).
  ModelSolution solve(const Xyz& target, double upper) const override;

 private:
  struct Exemplar {
    std::vector<double> rho;  // on the grid, in [0, 1]
    Lab lab;                  // of the measured reflectance, relative to rho == 1
    LabMetric metric;         // CIEDE2000's at lab
  };
  std::vector<Xyz> columns_;
  Xyz white_;  // W . 1
  NaturalSolver solver_;
  std::vector<Exemplar> exemplars_;
};

/// The measured reflectances of the development sets (ColorChecker, then AMPAS 190; `sets`
/// picks by file name, empty = both) at `wavelengths` (linear interpolation of the stored 5 nm
/// samples, their end values beyond 380..780 nm), as measured (not clamped). Throws Error if
/// a file is missing. Cost: O(patches x N).
std::vector<std::vector<double>> development_reflectances(std::span<const double> wavelengths,
                                                          std::span<const std::string> sets = {});

/// The data files of the development sets, ColorChecker first. Cost: O(1).
std::vector<std::string> development_set_files();

/// The registry entry of the exemplar model. Cost: O(1).
ModelInfo exemplar_model_info();

}  // namespace spectralize
