#include "path_tracer/wavelengths.h"

#include <algorithm>
#include <cmath>

namespace spectralize::path_tracer {

namespace {

constexpr double kMinNm = 360, kMaxNm = 830;
// The pdf's shape: sech^2 of a(l - centre), normalised on [kMinNm, kMaxNm].
constexpr double kRate = 0.0072, kCentre = 538;

double tanh_at(double nm) {
  return std::tanh(kRate * (nm - kCentre));
}

}  // namespace

SpectralFilm::SpectralFilm(const Observer& observer) : cmf_(observer.cmf), k_(observer.y_integral) {
  const std::size_t n = ReferenceTable::kSize;
  for (std::size_t k = 0; k < n; k += kLanes) {
    WavelengthPacket p;
    for (int i = 0; i < kLanes; ++i) {
      const std::size_t j = k + static_cast<std::size_t>(i);
      // The padding lane repeats the last wavelength with no weight.
      const std::size_t t = std::min(j, n - 1);
      p.nm[i] = static_cast<float>(ReferenceTable::wavelength(t));
      const double w = j < n ? ReferenceTable::trapezoid(j) / k_ : 0.0;
      for (int c = 0; c < 3; ++c) p.xyz_weight[c][i] = static_cast<float>(w * cmf_[c][t]);
    }
    reference_.push_back(p);
  }
}

double SpectralFilm::visible_pdf(double nm) {
  if (!(nm >= kMinNm && nm <= kMaxNm)) return 0;
  const double c = std::cosh(kRate * (nm - kCentre));
  return kRate / (c * c) / (tanh_at(kMaxNm) - tanh_at(kMinNm));
}

double SpectralFilm::sample_visible(double u) {
  // CDF(l) = (tanh(a (l - c)) - tanh(a (min - c))) / (tanh(a (max - c)) - tanh(a (min - c))).
  const double lo = tanh_at(kMinNm), hi = tanh_at(kMaxNm);
  const double nm = kCentre + std::atanh(lo + u * (hi - lo)) / kRate;
  return std::clamp(nm, kMinNm, kMaxNm);
}

std::array<double, 3> SpectralFilm::cmf(double nm) const {
  if (!(nm >= kMinNm && nm <= kMaxNm)) return {0, 0, 0};
  const double x = nm - kMinNm;
  const std::size_t k = std::min(static_cast<std::size_t>(x), ReferenceTable::kSize - 2);
  const double f = x - static_cast<double>(k);
  std::array<double, 3> out;
  for (int c = 0; c < 3; ++c) out[c] = ((1 - f) * cmf_[c][k] + f * cmf_[c][k + 1]) / k_;
  return out;
}

WavelengthPacket SpectralFilm::hero(double u) const {
  WavelengthPacket p;
  for (int i = 0; i < kLanes; ++i) {
    double up = u + static_cast<double>(i) / kLanes;
    if (up >= 1) up -= 1;
    // The film weighs the wavelength the spectra are evaluated at (the float).
    p.nm[i] = static_cast<float>(sample_visible(up));
    const double nm = p.nm[i];
    const double w = 1.0 / (kLanes * visible_pdf(nm));
    const std::array<double, 3> c = cmf(nm);
    for (int k = 0; k < 3; ++k) p.xyz_weight[k][i] = static_cast<float>(w * c[k]);
  }
  return p;
}

}  // namespace spectralize::path_tracer
