// The natural model (--model natural): optimality from the definition (the spectrum's link z is
// stationary for sum (z[i+1] - z[i])^2 on the exact spectra: grad = L'(z) . W^T lambda),
// smoother in its link than the other exact interior spectra, and a fallback near the gamut
// boundary that is counted. Exactness and bounds on random colours of three spaces are in
// bounded_models_test.cpp (parametrised over models); the solver's depth and the continuity of
// its fallback in natural_solver_test.cpp.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "spectralize/core/spectralizer.h"
#include "spectralizer_checks.h"
#include "test_support.h"

namespace spectralize {
namespace {

using namespace test;  // NOLINT: the checks of spectralizer_checks.h

Spectralizer make_natural(Mode mode) {
  SpectralizerSettings s;
  s.mode = mode;
  s.model = "natural";
  return Spectralizer(s);
}

// The link of a spectrum, written out from the definition: x = upper (tanh z + 1) / 2 for a
// reflectance, x = e^z for a light; and its derivative dx/dz.
double link(double x, double upper) {
  return std::isinf(upper) ? std::log(x) : std::atanh(2 * x / upper - 1);
}
double link_slope(double x, double upper) {
  return std::isinf(upper) ? x : 2 * x * (upper - x) / upper;
}

double link_roughness(const std::vector<double>& x, double upper) {
  double r = 0;
  for (std::size_t i = 0; i + 1 < x.size(); ++i) {
    const double d = link(x[i + 1], upper) - link(x[i], upper);
    r += d * d;
  }
  return r;
}

// Stationarity of min 1/2 sum (dz)^2 s.t. W L(z) = t: g = D^T D z equals L'(z) (W^T lambda)
// for some lambda. lambda by least squares of g_i / L'_i = c_i . lambda; the worst residual
// relative to max |g| (0 at the optimum).
double stationarity_violation(const Spectralizer& sp, const std::vector<double>& x, double upper) {
  const std::size_t n = x.size();
  std::vector<double> z(n);
  for (std::size_t i = 0; i < n; ++i) z[i] = link(x[i], upper);
  // g = D^T D z, element by element.
  auto g = [&](std::size_t i) {
    return (i > 0 ? z[i] - z[i - 1] : 0.0) - (i + 1 < n ? z[i + 1] - z[i] : 0.0);
  };
  double scale = 0;
  for (std::size_t i = 0; i < n; ++i) scale = std::max(scale, std::abs(g(i)));
  if (scale < 1e-9) return 0;  // flat: the optimum trivially
  const auto& c = sp.weights().columns();
  // Weighted least squares: minimise sum (g_i - s_i c_i . lambda)^2, s_i = L'(z_i).
  Mat3 a{};
  Xyz rhs;
  for (std::size_t i = 0; i < n; ++i) {
    const double s = link_slope(x[i], upper);
    const Xyz v = s * c[i];
    for (int r = 0; r < 3; ++r) {
      for (int q = 0; q < 3; ++q) a[r][q] += v[r] * v[q];
      rhs[r] += v[r] * g(i);
    }
  }
  const Xyz lambda = mul(inverse(a), rhs);
  double worst = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Xyz v = link_slope(x[i], upper) * c[i];
    worst = std::max(worst, std::abs(g(i) - (v.X * lambda.X + v.Y * lambda.Y + v.Z * lambda.Z)));
  }
  return worst / scale;
}

TEST(NaturalModel, SpectraAreStationaryForTheLinkRoughnessAndSmootherThanOthers) {
  // 400 random Rec.2020 colours per mode solved in the natural zone: stationary to 1e-7 of the
  // gradient's scale (Newton stops at steps below 1e-9), strictly inside the bounds, and no
  // rougher in the link than the smooth model's spectrum of the same colour where that one is
  // strictly inside the bounds too (so it is a feasible point of the same programme).
  std::mt19937 rng(99);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (Mode mode : {Mode::emission, Mode::reflectance}) {
    const Spectralizer natural = make_natural(mode);
    SpectralizerSettings ss;
    ss.mode = mode;
    ss.model = "smooth";
    const Spectralizer smooth(ss);
    const double upper = mode == Mode::reflectance ? 1.0 : std::numeric_limits<double>::infinity();
    double worst = 0;
    int checked = 0, compared = 0;
    for (int i = 0; i < 400; ++i) {
      const Xyz xyz = rgb(kRec2020ToXyz, u(rng), u(rng), u(rng));
      const SpectrumResult r = natural.spectralize(xyz);
      if (r.status != Outcome::exact || r.fallback) continue;
      ++checked;
      for (double v : r.values) {
        ASSERT_GT(v, 0.0);
        ASSERT_LT(v, upper);
      }
      const double v = stationarity_violation(natural, r.values, upper);
      worst = std::max(worst, v);
      EXPECT_LE(v, 1e-7) << "colour " << i << " " << to_string(mode);
      const SpectrumResult s = smooth.spectralize(xyz);
      if (std::all_of(s.values.begin(), s.values.end(),
                      [&](double x) { return x > 1e-9 && x < upper - 1e-9; })) {
        ++compared;
        EXPECT_LE(link_roughness(r.values, upper), link_roughness(s.values, upper) * (1 + 1e-9));
      }
    }
    std::printf("  %s: %d stationary spectra checked (worst %.1e), %d compared with smooth\n",
                std::string(to_string(mode)).c_str(), checked, worst, compared);
    EXPECT_GT(checked, 300);
    EXPECT_GT(compared, 20);
  }
}

TEST(NaturalModel, FallbackIsCountedAndOnlyNearTheBoundary) {
  // sRGB colours are all deep inside the natural zone (measured: depth <= 0.99); among random
  // Rec.2020 reflectances the ones near the solid's boundary take the fallback (measured ~8%),
  // each reporting its weight in (0, 1]; lights almost never (the locus is far).
  for (Mode mode : {Mode::reflectance, Mode::emission}) {
    const Spectralizer sp = make_natural(mode);
    for (const Space& space : {spaces()[0], spaces()[1]}) {
      std::mt19937 rng(5);
      std::uniform_real_distribution<double> u(0.0, 1.0);
      int fallbacks = 0;
      const int n = 2000;
      for (int i = 0; i < n; ++i) {
        const SpectrumResult r = sp.spectralize(rgb(space.to_xyz, u(rng), u(rng), u(rng)));
        const double w = r.detail("fallback_weight");
        if (r.fallback) {
          ++fallbacks;
          EXPECT_GT(w, 0.0);
          EXPECT_LE(w, 1.0);
        } else {
          EXPECT_EQ(w, 0.0);
        }
      }
      const double rate = static_cast<double>(fallbacks) / n;
      std::printf("  %s %s: fallback %.2f%%\n", space.name, std::string(to_string(mode)).c_str(),
                  100 * rate);
      if (std::string(space.name) == "Linear Rec.709") {
        EXPECT_EQ(fallbacks, 0);
      }
      if (mode == Mode::reflectance && std::string(space.name) == "Linear Rec.2020") {
        EXPECT_GT(rate, 0.02);
        EXPECT_LT(rate, 0.20);
      }
      if (mode == Mode::emission) {
        EXPECT_LT(rate, 0.01);
      }
    }
  }
}

}  // namespace
}  // namespace spectralize
