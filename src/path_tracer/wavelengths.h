#pragma once
// Which wavelengths a path carries and how their values become CIE XYZ. A renderer's way
// (pbrt-v4's SampledWavelengths::SampleVisible): four wavelengths per path, one random offset u
// and its three rotations by quarters, through the inverse CDF of a visible-wavelength pdf over
// 360-830 nm; the film adds f(lambda) cmf(lambda) / (4 pdf(lambda) K). The dense reference: all
// 471 points of the 1 nm reference table with their trapezoid weights (docs/DESIGN.md §3), the
// same integral without noise.

#include <array>
#include <cstddef>
#include <vector>

#include "spectralize/core/colorimetry.h"

namespace spectralize::path_tracer {

/// Wavelengths per packet: what one spz_eval4 call evaluates.
inline constexpr int kLanes = 4;

/// Four wavelengths and, per CIE component, the factor that turns a spectral value at each into
/// its share of the pixel's XYZ: XYZ_c += sum_i xyz_weight[c][i] * f(nm[i]).
struct WavelengthPacket {
  std::array<float, kLanes> nm{};
  std::array<std::array<float, kLanes>, 3> xyz_weight{};
};

/// Film and wavelength tables of one observer; immutable, thread-safe.
class SpectralFilm {
 public:
  /// Reads the observer's 1 nm tables. Cost: O(471).
  explicit SpectralFilm(const Observer& observer);

  /// The visible-wavelength pdf (per nm): p(l) = a sech^2(a (l - 538)) / (tanh(a (830 - 538)) -
  /// tanh(a (360 - 538))) on 360..830 nm, a = 0.0072 / nm, 0 outside: the shape pbrt-v4 samples
  /// (close to the sum of the matching functions). Cost: O(1).
  static double visible_pdf(double nm);
  /// Its inverse CDF: the wavelength at probability u in [0, 1). Cost: O(1).
  static double sample_visible(double u);

  /// The hero packet of offset u in [0, 1): wavelengths at u, u + 1/4, u + 1/2, u + 3/4 (mod 1)
  /// through sample_visible, each weighted 1 / (4 pdf K). Cost: O(1).
  WavelengthPacket hero(double u) const;
  /// The dense packets: 360..830 nm at 1 nm with trapezoid weights / K, 118 packets (the last
  /// padded by a zero weight). Cost: O(1).
  const std::vector<WavelengthPacket>& reference() const { return reference_; }
  /// The matching functions / K at any wavelength: linear between the 1 nm table points, 0
  /// outside 360..830. Cost: O(1).
  std::array<double, 3> cmf(double nm) const;
  /// K = sum tau ybar, the observer's Y integral. Cost: O(1).
  double y_integral() const { return k_; }

 private:
  std::array<std::vector<double>, 3> cmf_;
  double k_ = 0;
  std::vector<WavelengthPacket> reference_;
};

}  // namespace spectralize::path_tracer
