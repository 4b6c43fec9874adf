#pragma once
// The comparison baseline: Jakob & Hanika, "A Low-Dimensional Function Space for Efficient
// Spectral Upsampling" (EGSR 2019), what pbrt-v4 and Mitsuba 3 do at render time. Not part of the
// product (tool, plugin, Python module, install); src/figures and tests/bench link it.
//
// The spectrum of a reflectance colour is s(lambda) = 1/2 + x / (2 sqrt(1 + x^2)) with
// x = c0 lambda^2 + c1 lambda + c2, lambda in nm. The three coefficients of an RGB colour are
// fitted by Levenberg-Marquardt on the CIELAB (Delta E 1976) residual between the target and the
// colour of s. The fit works in the normalised wavelength t = (lambda - 360) / 470 on [0, 1] (the
// CIE tables' range, as rgb2spec does), where the coefficients are of order 1..100; they are
// converted to nm (and to float) for storage and evaluation, as renderers hold them. Like
// rgb2spec, the fit bounds the largest coefficient (SigmoidFitterSettings::max_coefficient).
//
// Colorimetry is the project's, not rgb2spec's own quadrature: s is sampled on the grid and read
// as the piecewise-linear spectrum through the samples, integrated with the reference weights of
// docs/DESIGN.md §3 (1 nm CIE tables, SampleWeights) under the reference illuminant (D65), and the
// target is the space's XYZ white-balanced by XYZ scaling to the colour of rho == 1 (§3), so both
// methods are measured against the same truth. A renderer evaluates s at continuous wavelengths;
// at the default 5 nm grid the two colours differ far below the fit's own error.
//
// The table (pbrt-v4's RGBToSpectrumTable layout): for each "largest component" block m (0 = R,
// 1 = G, 2 = B), res^3 nodes of 3 float coefficients indexed [m][z][y][x]: z = that component on
// the scale smoothstep(smoothstep(k / (res - 1))), x and y the components (m + 1) % 3 and
// (m + 2) % 3 divided by it, at i / (res - 1). A fetch trilinearly blends the 8 coefficients
// around the colour; equal components take the exact constant spectrum instead. The table is
// filled by continuation from the middle of the z range (rgb2spec starts at k = res / 5; the
// solutions are the same where the fit converges, only the starting points differ).
//
// Measured (sRGB, 64^3, 20000 random colours; tests/bench/sigmoid_study): the direct fit reaches
// every colour (Delta E 76 < 1e-6), through the table max 1.33, mean 0.06.

#include <array>
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#ifdef __SSE2__
#include <emmintrin.h>
#endif

#include "spectralize/core/sample_weights.h"
#include "spectralize/core/wavelength_grid.h"
#include "spectralize/core/xyz.h"

namespace spectralize::baseline {

/// An RGB -> CIE XYZ (D65) matrix, rows X, Y, Z.
using RgbToXyz = std::array<std::array<double, 3>, 3>;

/// |x| beyond which s rounds to 0 or 1 and x^2 still does not overflow: clamping there instead
/// of testing for +-inf (pbrt's way) gives the same values without a branch, also for finite
/// |x| so large that x^2 would overflow (where the unclamped formula gives 1/2).
template <typename T>
inline constexpr T kSigmoidClamp = sizeof(T) == sizeof(float) ? T(1e18) : T(1e150);

/// The sigmoid of the polynomial: s = 1/2 + x / (2 sqrt(1 + x^2)), x = +-inf (the constant
/// spectra 1 and 0) exactly. Cost: O(1), one square root and one division.
template <typename T>
inline T sigmoid(T x) {
  x = x < -kSigmoidClamp<T> ? -kSigmoidClamp<T> : (x > kSigmoidClamp<T> ? kSigmoidClamp<T> : x);
  return T(0.5) + x / (2 * std::sqrt(1 + x * x));
}

/// The coefficients of x(lambda) = c0 lambda^2 + c1 lambda + c2 (lambda in nm) and the spectrum
/// they define. Float is what renderers store and evaluate; double serves the validation.
template <typename T>
struct BasicSigmoidPolynomial {
  T c0 = 0, c1 = 0, c2 = 0;

  /// The spectrum's value at `nm`. Horner form with plain multiply-adds (std::fma is a library
  /// call on x86-64 without -mfma). Cost: O(1), one square root.
  T operator()(T nm) const { return sigmoid((c0 * nm + c1) * nm + c2); }
  /// The spectrum at 4 wavelengths (a renderer's sample), out[i] at nm[i], bit-identical to 4
  /// calls of operator() (float: one SSE lane each). Cost: O(1).
  void eval4(const T* nm, T* out) const {
#ifdef __SSE2__
    if constexpr (sizeof(T) == sizeof(float)) {
      // The square root in a loop is not vectorised while sqrt may set errno: written out.
      const __m128 l = _mm_loadu_ps(nm), big = _mm_set1_ps(kSigmoidClamp<float>);
      __m128 x = _mm_add_ps(_mm_mul_ps(_mm_set1_ps(c0), l), _mm_set1_ps(c1));
      x = _mm_add_ps(_mm_mul_ps(x, l), _mm_set1_ps(c2));
      x = _mm_min_ps(_mm_max_ps(x, _mm_sub_ps(_mm_setzero_ps(), big)), big);
      const __m128 one = _mm_set1_ps(1.0f), half = _mm_set1_ps(0.5f);
      const __m128 root = _mm_sqrt_ps(_mm_add_ps(one, _mm_mul_ps(x, x)));
      _mm_storeu_ps(out, _mm_add_ps(half, _mm_div_ps(x, _mm_add_ps(root, root))));
      return;
    }
#endif
    for (int i = 0; i < 4; ++i) out[i] = (*this)(nm[i]);
  }
};
using SigmoidPolynomial = BasicSigmoidPolynomial<float>;

/// One colour's fit.
struct SigmoidFit {
  std::array<double, 3> normalised{};         // (a, b, c) of a t^2 + b t + c, t = (nm - 360) / 470
  BasicSigmoidPolynomial<double> polynomial;  // the same in nm
  double delta_e76 = 0;                       // CIELAB distance of s's colour from the target
  int iterations = 0;
};

/// The nm coefficients of a t^2 + b t + c with t = (nm - 360) / 470. Cost: O(1).
BasicSigmoidPolynomial<double> to_nm(const std::array<double, 3>& normalised);

/// How colours are measured and fitted.
struct SigmoidFitterSettings {
  WavelengthGrid grid;               // where s is sampled (default 380:780:5)
  std::string observer = "cie1931";  // a name Observer::get accepts
  std::string illuminant = "D65";    // the reference illuminant, a name Illuminant::get accepts
  // rgb2spec's bound on the largest normalised coefficient (all three scaled down to it). It
  // keeps unreachable colours of wide-gamut spaces finite in float; in sRGB it limits dark
  // saturated colours (largest component < 0.03: up to 1.1 Delta E 76) and near-whites (up to
  // 0.07). INFINITY: the sigmoid's own limit.
  double max_coefficient = 200;
};

/// Fits sigmoid spectra to linear RGB colours of one space, as reflectances under the reference
/// illuminant (docs/DESIGN.md §3). Immutable after construction: thread-safe.
class SigmoidFitter {
 public:
  /// `rgb_to_xyz` takes the space's linear RGB to CIE XYZ (D65-referred, Y = 1 for white).
  /// Throws Error for an unknown observer or illuminant or a max_coefficient <= 0.
  /// Cost: O(471 + N).
  explicit SigmoidFitter(const RgbToXyz& rgb_to_xyz, const SigmoidFitterSettings& settings = {});

  /// The best sigmoid spectrum of linear RGB `rgb` (any values; colours the sigmoid cannot reach
  /// get the least-squares one within the bound), by Levenberg-Marquardt from `start`
  /// (normalised coefficients; zero is the flat spectrum 1/2). Stops at Delta E 1e-6, when no
  /// step descends, or after `max_iterations`. Cost: O(N) per iteration; ~7 us per colour from
  /// the flat start at N = 81 (measured by tests/bench/sigmoid_study), less from a neighbour's.
  SigmoidFit fit(const std::array<double, 3>& rgb, const std::array<double, 3>& start = {},
                 int max_iterations = 50) const;

  /// The white-balanced XYZ target of `rgb` (reference white = the XYZ of rho == 1). Cost: O(1).
  Xyz target_of(const std::array<double, 3>& rgb) const;
  /// The XYZ of the sigmoid spectrum of `p` sampled on the grid. Cost: O(N).
  Xyz xyz_of(const BasicSigmoidPolynomial<double>& p) const;
  /// The samples of `p`'s spectrum on the grid. Cost: O(N).
  std::vector<double> spectrum(const BasicSigmoidPolynomial<double>& p) const;
  /// The XYZ of rho == 1: the white of CIELAB. Cost: O(1).
  Xyz reference_white() const { return weights_.unit_white(); }
  const WavelengthGrid& grid() const { return grid_; }

 private:
  RgbToXyz rgb_to_xyz_;
  WavelengthGrid grid_;
  SampleWeights weights_;
  Xyz balance_;            // W_ref / W_D65 per component (docs/DESIGN.md §3)
  std::vector<double> t_;  // normalised wavelength of each grid sample
  double max_coefficient_;
};

/// pbrt-v4's RGBToSpectrumTable: 3 x res^3 nodes of float nm coefficients (layout above).
class SigmoidTable {
 public:
  /// Fits every node with `fitter`: per block and y row, from the grey end x = 1 at the middle of
  /// the z range inward in x, then per (x, y) outward in z both ways, each fit starting from its
  /// neighbour's solution (the paper's continuation). res >= 2; `threads` workers (std::thread).
  /// Cost: 3 res^3 fits; res 64: 5 s of CPU (sigmoid_study), halved in wall time by 2 threads.
  explicit SigmoidTable(const SigmoidFitter& fitter, int resolution = 64, int threads = 2);

  /// The coefficients of linear RGB (r, g, b), each in [0, 1] (renderers clamp first), by
  /// trilinear interpolation of the nodes; equal components give the exact constant spectrum.
  /// Inline, no allocation: the speed baseline. Cost: O(log res) (the z interval's search).
  SigmoidPolynomial operator()(float r, float g, float b) const {
    if (r == g && g == b) return {0, 0, (r - 0.5f) / std::sqrt(r * (1 - r))};
    const float rgb[3] = {r, g, b};
    const int m = (r > g) ? (r > b ? 0 : 2) : (g > b ? 1 : 2);
    const float z = rgb[m];
    const float scale = static_cast<float>(res_ - 1) / z;
    const float x = rgb[(m + 1) % 3] * scale, y = rgb[(m + 2) % 3] * scale;
    const int xi = x < static_cast<float>(res_ - 2) ? static_cast<int>(x) : res_ - 2;
    const int yi = y < static_cast<float>(res_ - 2) ? static_cast<int>(y) : res_ - 2;
    const int zi = z_interval(z);
    const float dx = x - static_cast<float>(xi), dy = y - static_cast<float>(yi);
    const float dz = (z - z_nodes_[zi]) / (z_nodes_[zi + 1] - z_nodes_[zi]);
    // Node (m, k, j, i) starts at float 3 * (((m res + k) res + j) res + i).
    const std::size_t sx = 3, sy = sx * res_, sz = sy * res_;
    const float* c = coefficients_.data() +
                     sx * static_cast<std::size_t>(((m * res_ + zi) * res_ + yi) * res_ + xi);
    float out[3];
    for (int q = 0; q < 3; ++q) {
      const float* p = c + q;
      const float x00 = p[0] + dx * (p[sx] - p[0]);
      const float x10 = p[sy] + dx * (p[sy + sx] - p[sy]);
      const float x01 = p[sz] + dx * (p[sz + sx] - p[sz]);
      const float x11 = p[sz + sy] + dx * (p[sz + sy + sx] - p[sz + sy]);
      const float y0 = x00 + dy * (x10 - x00), y1 = x01 + dy * (x11 - x01);
      out[q] = y0 + dz * (y1 - y0);
    }
    return {out[0], out[1], out[2]};
  }

  /// The stored coefficients of node (block m, z index k, y index j, x index i). Cost: O(1).
  SigmoidPolynomial node(int m, int k, int j, int i) const {
    const float* c =
        coefficients_.data() + 3 * static_cast<std::size_t>(((m * res_ + k) * res_ + j) * res_ + i);
    return {c[0], c[1], c[2]};
  }
  /// The largest component at z index k: smoothstep(smoothstep(k / (res - 1))). Cost: O(1).
  float z_node(int k) const { return z_nodes_[k]; }
  int resolution() const { return res_; }
  /// The largest Delta E 1976 of any node's own fit (the table's worst node). Cost: O(1).
  double max_node_delta_e() const { return max_node_delta_e_; }

 private:
  // The last k in [0, res - 2] with z_nodes_[k] <= z (z >= 0), by bisection with a fixed
  // number of steps and a conditional move each (no data-dependent branch).
  int z_interval(float z) const {
    const float* base = z_nodes_.data();
    for (int n = res_ - 1; n > 1;) {  // the answer lies in [base, base + n)
      const int half = n / 2;
      base = base[half] <= z ? base + half : base;
      n -= half;
    }
    return static_cast<int>(base - z_nodes_.data());
  }

  int res_;
  std::vector<float> z_nodes_;
  std::vector<float> coefficients_;  // 3 * 3 * res^3
  double max_node_delta_e_ = 0;
};

}  // namespace spectralize::baseline
