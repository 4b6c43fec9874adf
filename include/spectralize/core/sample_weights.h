#pragma once
// Tristimulus weights of each grid sample under the reference integration (docs/DESIGN.md §3):
// W_i = sum_k tau_k * cmf(lambda_k) * E(lambda_k) * h_i(lambda_k) / norm, where h_i is the tent
// of sample i, so that W . phi is exactly the trapezoid integral of the piecewise-linear
// spectrum phi on the 1 nm CIE tables.

#include <span>
#include <vector>

#include "spectralize/core/colorimetry.h"
#include "spectralize/core/wavelength_grid.h"
#include "spectralize/core/xyz.h"

namespace spectralize {

/// Value at wavelength `nm` of the piecewise-linear spectrum through `values` on `grid`, zero
/// outside [start, end]. Cost: O(1).
double piecewise_linear(const WavelengthGrid& grid, std::span<const double> values, double nm);

/// XYZ of a piecewise-linear spectrum by direct trapezoid integration on the 1 nm tables,
/// optionally times an illuminant, divided by `norm`. Independent of SampleWeights (used to
/// check it). Cost: O(471).
Xyz integrate_reference(const WavelengthGrid& grid, std::span<const double> values,
                        const Observer& observer, const Illuminant* illuminant, double norm);

/// Raw tristimulus weights (cmf * E * tent, trapezoid on the 1 nm tables, not normalised) of
/// piecewise-linear spectra sampled at increasing wavelengths `nm` (any spacing; zero outside
/// [nm.front(), nm.back()]). Throws Error unless nm is strictly increasing with >= 2 samples.
/// Cost: O(471 log N + N).
std::vector<Xyz> tent_weights(std::span<const double> nm, const Observer& observer,
                              const Illuminant* illuminant);

class SampleWeights {
 public:
  /// Emission weights (illuminant == nullptr; normalised by K = sum tau ybar, so a constant
  /// spectrum v has Y ~= v) or reflectance weights (normalised so rho == 1 has Y = 1).
  /// Cost: O(471 + N).
  SampleWeights(const WavelengthGrid& grid, const Observer& observer, const Illuminant* illuminant);
  /// The same for arbitrary increasing wavelengths (e.g. a file's bands). Throws Error.
  /// Cost: O(471 log N + N).
  SampleWeights(std::span<const double> wavelengths_nm, const Observer& observer,
                const Illuminant* illuminant);

  /// The weight vector (X, Y, Z) of each sample. Cost: O(1).
  const std::vector<Xyz>& columns() const { return columns_; }
  /// W . phi: the XYZ of a spectrum on this grid. Cost: O(N).
  Xyz integrate(std::span<const double> spectrum) const;
  /// The XYZ of the constant spectrum 1 (reflectance: the reference white, Y = 1). Cost: O(1).
  Xyz unit_white() const { return white_; }
  /// The normalisation divided out of the raw sums. Cost: O(1).
  double normalisation() const { return norm_; }

 private:
  std::vector<Xyz> columns_;
  Xyz white_;
  double norm_ = 1;
};

}  // namespace spectralize
