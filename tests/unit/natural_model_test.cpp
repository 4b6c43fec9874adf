// The natural model (--model natural): optimality from the definition (the spectrum's link z is
// stationary for sum (z[i+1] - z[i])^2 on the exact spectra: grad = L'(z) . W^T lambda),
// smoother in its link than the other exact interior spectra, and a fallback near the gamut
// boundary that is counted, continuous (no seam in a gradient) and exact. Exactness and bounds
// on random colours of three spaces are in bounded_models_test.cpp (parametrised over models).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "core/natural_solver.h"
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
  std::vector<double> z(n), g(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) z[i] = link(x[i], upper);
  for (std::size_t i = 0; i + 1 < n; ++i) {
    g[i] -= z[i + 1] - z[i];
    g[i + 1] += z[i + 1] - z[i];
  }
  double scale = 0;
  for (double v : g) scale = std::max(scale, std::abs(v));
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
      rhs[r] += v[r] * g[i];
    }
  }
  const Xyz lambda = mul(inverse(a), rhs);
  double worst = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Xyz v = link_slope(x[i], upper) * c[i];
    worst = std::max(worst, std::abs(g[i] - (v.X * lambda.X + v.Y * lambda.Y + v.Z * lambda.Z)));
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

// The largest change of the spectrum between neighbours of a walk of `steps` steps from depth
// d0 to d1 along the ray from the grey of `colour`'s luminance through `colour`; counts the
// fallback solves and checks exactness and bounds on the way.
struct Walk {
  double max_jump = 0;
  int fallbacks = 0, natural = 0;
  double weight_first = -1, weight_last = -1;
};
Walk walk(const NaturalSolver& solver, const Spectralizer& sp, const Xyz& grey, const Xyz& dir,
          double s_boundary, double d0, double d1, int steps, double upper) {
  Walk w;
  std::vector<double> prev;
  double prev_weight = 0;
  for (int k = 0; k <= steps; ++k) {
    const double d = d0 + (d1 - d0) * k / steps;
    const Xyz t = grey + (d * s_boundary) * dir;
    const NaturalSpectrum r = solver.solve(t, upper);
    EXPECT_TRUE(r.converged) << "depth " << d;
    EXPECT_LE(rel_err(sp.weights().integrate(r.values), t), 1e-12) << "depth " << d;
    for (double v : r.values) {
      EXPECT_GE(v, 0.0);
      EXPECT_LE(v, upper);
    }
    (r.fallback ? w.fallbacks : w.natural)++;
    EXPECT_GE(r.fallback_weight, prev_weight - 1e-12);  // rises monotonically with depth
    prev_weight = r.fallback_weight;
    if (k == 0) w.weight_first = r.fallback_weight;
    w.weight_last = r.fallback_weight;
    if (!prev.empty()) {
      double jump = 0, top = 0;
      for (std::size_t i = 0; i < prev.size(); ++i) {
        jump = std::max(jump, std::abs(r.values[i] - prev[i]));
        top = std::max(top, prev[i]);
      }
      w.max_jump = std::max(w.max_jump, jump / top);
    }
    prev = r.values;
  }
  return w;
}

TEST(NaturalModel, FallbackIsContinuousAcrossItsThreshold) {
  // A gradient that crosses the natural zone's edge (depth 0.999) toward the gamut boundary,
  // walked in 30 and in 300 steps: a continuous path's largest step shrinks ~10x with the step,
  // a seam would keep its jump. Six Rec.2020 hues, both modes; the walk ends at depth 0.9995.
  for (Mode mode : {Mode::reflectance, Mode::emission}) {
    const Spectralizer sp = make_natural(mode);
    const NaturalSolver solver(sp.weights().columns(), 5.0);
    const double upper = mode == Mode::reflectance ? 1.0 : std::numeric_limits<double>::infinity();
    // The solver's own reference: the flat spectrum (the grey of a reflectance, the
    // equal-energy white of a light), along whose luminance rays the depth is measured.
    const Xyz white = sp.weights().integrate(std::vector<double>(sp.settings().grid.size(), 1.0));
    for (const auto& c : std::vector<std::array<double, 3>>{{1, 0.1, 0.05},
                                                            {0.1, 1, 0.1},
                                                            {0.1, 0.2, 1},
                                                            {1, 1, 0.05},
                                                            {0.05, 1, 1},
                                                            {1, 0.1, 1}}) {
      const Xyz colour = 0.4 * rgb(kRec2020ToXyz, c[0], c[1], c[2]);
      const Xyz grey = (colour.Y / white.Y) * white;
      const Xyz dir = colour - grey;
      const double depth = solver.depth(colour, upper);
      ASSERT_TRUE(std::isfinite(depth) && depth > 0) << depth;
      const double s_boundary = 1 / depth;  // depth is linear along the ray from the grey
      SCOPED_TRACE(std::string(to_string(mode)) + " colour " + std::to_string(c[0]) + "," +
                   std::to_string(c[1]) + "," + std::to_string(c[2]));
      EXPECT_NEAR(solver.depth(grey + (0.5 * s_boundary) * dir, upper), 0.5, 1e-9);
      const Walk coarse = walk(solver, sp, grey, dir, s_boundary, 0.998, 0.9995, 30, upper);
      const Walk fine = walk(solver, sp, grey, dir, s_boundary, 0.998, 0.9995, 300, upper);
      // Both sides of the threshold are walked.
      EXPECT_GT(fine.natural, 0);
      EXPECT_GT(fine.fallbacks, 0);
      EXPECT_EQ(fine.weight_first, 0.0);
      EXPECT_GT(fine.weight_last, 0.0);
      // No seam: the largest step shrinks with the step size (10x expected, 4x required).
      EXPECT_LE(fine.max_jump, 0.25 * coarse.max_jump)
          << "coarse " << coarse.max_jump << " fine " << fine.max_jump;
    }
  }
}

TEST(NaturalModel, DepthIsZeroOnTheGreyAndOneOnTheBoundary) {
  // The depth the fallback is decided by, against the gamut test of the Spectralizer: 0 on the
  // grey ray, 1 where in_gamut() flips (bisection, 1e-6), > 1 outside.
  const Spectralizer sp = make_natural(Mode::reflectance);
  const NaturalSolver solver(sp.weights().columns(), 5.0);
  const Xyz white = sp.reference_white();
  EXPECT_NEAR(solver.depth(0.3 * white, 1.0), 0.0, 1e-12);
  for (int h = 0; h < 12; ++h) {
    const double a = 2 * M_PI * h / 12;
    const Xyz grey = 0.3 * white;
    const double x0 = white.X / white.sum(), y0 = white.Y / white.sum();
    const Xyz dir = xyz_from_xy(x0 + 0.5 * std::cos(a), y0 + 0.5 * std::sin(a), 0.3) - grey;
    double lo = 0, hi = 1;
    if (sp.in_gamut(grey + dir)) continue;
    for (int k = 0; k < 60; ++k) {
      const double mid = 0.5 * (lo + hi);
      (sp.in_gamut(grey + mid * dir) ? lo : hi) = mid;
    }
    EXPECT_NEAR(solver.depth(grey + lo * dir, 1.0), 1.0, 1e-6) << "hue " << h;
    EXPECT_GT(solver.depth(grey + (1.01 * lo) * dir, 1.0), 1.0) << "hue " << h;
  }
}

}  // namespace
}  // namespace spectralize
