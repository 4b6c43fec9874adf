#include "core/sample_weights.h"

#include <cmath>

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

SampleWeights::SampleWeights(const WavelengthGrid& grid, const Observer& observer,
                             const Illuminant* illuminant)
    : grid_(grid), columns_(grid.size()) {
  // Emission: divide by K = sum tau ybar over the whole table (DESIGN §3). Reflectance: by the
  // Y of rho == 1 on this grid, so the reference white has Y = 1 exactly (set below).
  norm_ = 0;
  for (std::size_t k = 0; k < ReferenceTable::kSize; ++k)
    norm_ += ReferenceTable::trapezoid(k) * observer.cmf[1][k] * (illuminant ? 0.0 : 1.0);
  if (illuminant) norm_ = 1.0;

  // Each 1 nm table point falls in one grid interval and feeds the two tents spanning it.
  for (std::size_t k = 0; k < ReferenceTable::kSize; ++k) {
    double nm = ReferenceTable::wavelength(k);
    double u = (nm - grid.start()) / grid.step();
    double last = static_cast<double>(grid.size() - 1);
    if (u < 0 || u > last) continue;
    double w = ReferenceTable::trapezoid(k) * (illuminant ? illuminant->spd[k] : 1.0) / norm_;
    Xyz c{w * observer.cmf[0][k], w * observer.cmf[1][k], w * observer.cmf[2][k]};
    double i0 = std::floor(u);
    std::size_t i = static_cast<std::size_t>(i0);
    if (i0 >= last) {
      columns_[grid.size() - 1] = columns_[grid.size() - 1] + c;
      continue;
    }
    double t = u - i0;
    columns_[i] = columns_[i] + (1 - t) * c;
    columns_[i + 1] = columns_[i + 1] + t * c;
  }
  for (const Xyz& c : columns_) white_ = white_ + c;
  if (illuminant) {
    norm_ = white_.Y;
    for (Xyz& c : columns_) c = (1.0 / norm_) * c;
    white_ = Xyz{};
    for (const Xyz& c : columns_) white_ = white_ + c;
  }
}

Xyz SampleWeights::integrate(std::span<const double> spectrum) const {
  Xyz sum;
  for (std::size_t i = 0; i < columns_.size(); ++i) sum = sum + spectrum[i] * columns_[i];
  return sum;
}

}  // namespace spectralize
