#include "spectralize/core/sample_weights.h"

#include <algorithm>
#include <cmath>

#include "spectralize/core/error.h"

namespace spectralize {

double piecewise_linear(const WavelengthGrid& grid, std::span<const double> values, double nm) {
  double u = (nm - grid.start()) / grid.step();
  double last = static_cast<double>(grid.size() - 1);
  if (u < 0 || u > last) return 0.0;
  double i0 = std::floor(u);
  if (i0 >= last) return values[grid.size() - 1];
  std::size_t i = static_cast<std::size_t>(i0);
  double t = u - i0;
  return (1 - t) * values[i] + t * values[i + 1];
}

Xyz integrate_reference(const WavelengthGrid& grid, std::span<const double> values,
                        const Observer& observer, const Illuminant* illuminant, double norm) {
  Xyz sum;
  for (std::size_t k = 0; k < ReferenceTable::kSize; ++k) {
    double v = piecewise_linear(grid, values, ReferenceTable::wavelength(k));
    if (illuminant) v *= illuminant->spd[k];
    double w = ReferenceTable::trapezoid(k) * v;
    sum.X += w * observer.cmf[0][k];
    sum.Y += w * observer.cmf[1][k];
    sum.Z += w * observer.cmf[2][k];
  }
  return (1.0 / norm) * sum;
}

std::vector<Xyz> tent_weights(std::span<const double> nm, const Observer& observer,
                              const Illuminant* illuminant) {
  if (nm.size() < 2) throw Error("a spectrum needs at least 2 wavelengths");
  for (std::size_t i = 1; i < nm.size(); ++i)
    if (!(nm[i] > nm[i - 1]))
      throw Error("wavelengths must be strictly increasing (" + std::to_string(nm[i - 1]) +
                  " nm, then " + std::to_string(nm[i]) + " nm)");
  std::vector<Xyz> columns(nm.size());
  // Each 1 nm table point inside the samples' range feeds the two tents spanning it.
  for (std::size_t k = 0; k < ReferenceTable::kSize; ++k) {
    const double l = ReferenceTable::wavelength(k);
    if (l < nm.front() || l > nm.back()) continue;
    const double w = ReferenceTable::trapezoid(k) * (illuminant ? illuminant->spd[k] : 1.0);
    const Xyz c{w * observer.cmf[0][k], w * observer.cmf[1][k], w * observer.cmf[2][k]};
    std::size_t i =
        static_cast<std::size_t>(std::upper_bound(nm.begin(), nm.end(), l) - nm.begin());
    if (i == nm.size()) {  // exactly the last sample
      columns.back() = columns.back() + c;
      continue;
    }
    --i;
    const double t = (l - nm[i]) / (nm[i + 1] - nm[i]);
    columns[i] = columns[i] + (1 - t) * c;
    columns[i + 1] = columns[i + 1] + t * c;
  }
  return columns;
}

SampleWeights::SampleWeights(const WavelengthGrid& grid, const Observer& observer,
                             const Illuminant* illuminant)
    : SampleWeights(
          [&] {
            std::vector<double> nm(grid.size());
            for (std::size_t i = 0; i < nm.size(); ++i) nm[i] = grid[i];
            return nm;
          }(),
          observer, illuminant) {}

SampleWeights::SampleWeights(std::span<const double> wavelengths_nm, const Observer& observer,
                             const Illuminant* illuminant)
    : columns_(tent_weights(wavelengths_nm, observer, illuminant)) {
  // Emission: divide by K = sum tau ybar over the whole table (docs/DESIGN.md §3). Reflectance: by
  // the Y of rho == 1 on these wavelengths, so the reference white has Y = 1 exactly.
  Xyz raw_white;
  for (const Xyz& c : columns_) raw_white = raw_white + c;
  norm_ = illuminant ? raw_white.Y : observer.y_integral;
  for (Xyz& c : columns_) c = (1.0 / norm_) * c;
  for (const Xyz& c : columns_) white_ = white_ + c;
}

Xyz SampleWeights::integrate(std::span<const double> spectrum) const {
  Xyz sum;
  for (std::size_t i = 0; i < columns_.size(); ++i) sum = sum + spectrum[i] * columns_[i];
  return sum;
}

}  // namespace spectralize
