// NaturalSolver (src/core/solvers/natural_solver.h, docs/DESIGN.md §6): among the exact spectra of
// a target, the one whose link z (x = upper (tanh z + 1) / 2, or e^z for lights) is smoothest;
// exact to 1e-12 and strictly inside the bounds, homogeneous in the bound and (lights) in the
// target; the depth that decides the fallback (0 on the grey ray, 1 on the boundary, linear
// along the ray) and a fallback whose weight rises from the natural depth, continuous across
// it; targets without a solution answered within bounds, never a hang. Oracles: targets made
// as the colours (test_support.h's own integration) of known spectra, which are then feasible;
// the link roughness written out from its definition; bisection on the Spectralizer's gamut.

#include "core/solvers/natural_solver.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "spectralize/core/sample_weights.h"
#include "spectralize/core/spectralizer.h"
#include "spectralizer_checks.h"
#include "test_support.h"

namespace spectralize {
namespace {

using namespace test;  // NOLINT: the checks of spectralizer_checks.h

constexpr double kLight = std::numeric_limits<double>::infinity();

// The default grid's weights (reflectance under D65, or emission) and a solver on them.
struct OnGrid : test::DefaultGridWeights {
  NaturalSolver solver;
  explicit OnGrid(bool refl, double natural_depth = NaturalSolver::kNaturalDepth)
      : DefaultGridWeights(refl), solver(w.columns(), grid.step(), natural_depth) {}
  Xyz white() const { return colour(std::vector<double>(grid.size(), 1.0)); }
};

// A smooth random spectrum: reflectance in (0.05, 0.95), or a positive light.
std::vector<double> smooth_spectrum(std::mt19937& rng, std::size_t n, bool reflectance) {
  std::uniform_real_distribution<double> a(-0.15, 0.15), phase(0.0, 2 * M_PI);
  std::vector<double> s(n, 0.0);
  for (int k = 1; k <= 3; ++k) {
    const double ak = a(rng), pk = phase(rng);
    for (std::size_t i = 0; i < n; ++i)
      s[i] += ak * std::cos(k * M_PI * static_cast<double>(i) / static_cast<double>(n) + pk);
  }
  for (double& v : s) v = reflectance ? 0.5 + v : std::exp(6 * v);
  return s;
}

TEST(NaturalSolver, SolutionsAreExactStrictlyInsideTheBoundsAndSmootherThanTheirSource) {
  // Targets: the colours of 150 smooth random spectra per mode (feasible by construction). The
  // solution reproduces each to 1e-12 by the test's integration, is strictly inside the bounds,
  // and its link is no rougher than the source spectrum's, which has the same colour.
  for (bool reflectance : {true, false}) {
    SCOPED_TRACE(reflectance ? "reflectance" : "emission");
    const OnGrid s(reflectance);
    const double upper = reflectance ? 1.0 : kLight;
    std::mt19937 rng(reflectance ? 17 : 19);
    double worst = 0;
    for (int k = 0; k < 150; ++k) {
      const std::vector<double> source = smooth_spectrum(rng, s.grid.size(), reflectance);
      const Xyz t = s.colour(source);
      const NaturalSpectrum r = s.solver.solve(t, upper);
      ASSERT_TRUE(r.converged) << k;
      EXPECT_FALSE(r.safety_net);
      EXPECT_LT(r.iterations, 200);
      for (double v : r.values) {
        ASSERT_GT(v, 0.0);
        ASSERT_LT(v, upper);
      }
      worst = std::max(worst, rel_err(s.colour(r.values), t));
      EXPECT_LE(s.solver.roughness(r.values, upper), s.solver.roughness(source, upper) * (1 + 1e-9))
          << k;
    }
    EXPECT_LE(worst, 1e-12);
  }
}

TEST(NaturalSolver, RoughnessIsTheSquaredSlopeOfTheLinkPerNanometre) {
  // sum (z[i+1] - z[i])^2 / h with z = atanh(2 x / upper - 1) (reflectance) or log x (light),
  // written out here; +inf when a sample sits on a bound, where z is infinite.
  const OnGrid s(true);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.001, 0.999);
  const std::size_t n = s.grid.size();
  for (double upper : {1.0, 2.5, kLight}) {
    SCOPED_TRACE(upper);
    std::vector<double> x(n);
    for (double& v : x) v = std::isinf(upper) ? 10 * u(rng) : upper * u(rng);
    double want = 0;
    for (std::size_t i = 0; i + 1 < n; ++i) {
      const auto z = [&](double v) {
        return std::isinf(upper) ? std::log(v) : std::atanh(2 * v / upper - 1);
      };
      want += std::pow(z(x[i + 1]) - z(x[i]), 2);
    }
    want /= 5.0;
    EXPECT_NEAR(s.solver.roughness(x, upper), want, 1e-12 * want);
    EXPECT_EQ(
        s.solver.roughness(std::vector<double>(n, std::isinf(upper) ? 3.0 : 0.3 * upper), upper),
        0.0);  // flat
    std::vector<double> at_zero = x;
    at_zero[40] = 0.0;
    EXPECT_EQ(s.solver.roughness(at_zero, upper), INFINITY);
    if (!std::isinf(upper)) {
      std::vector<double> at_top = x;
      at_top[0] = upper;
      EXPECT_EQ(s.solver.roughness(at_top, upper), INFINITY);
    }
  }
}

TEST(NaturalSolver, GreysAreFlatAndWhiteIsTheBound) {
  // A flat spectrum has a flat link, zero roughness: every grey (and the equal-energy white of
  // a light, any brightness) is its own flat spectrum, to 1e-12; rho == upper is white itself.
  const OnGrid refl(true), light(false);
  const Xyz rw = refl.white(), lw = light.white();
  for (double upper : {1.0, 3.0}) {
    for (double p : {0.01, 0.18, 0.5, 0.97}) {
      const NaturalSpectrum r = refl.solver.solve((p * upper) * rw, upper);
      ASSERT_TRUE(r.converged) << p;
      EXPECT_FALSE(r.fallback);
      for (double v : r.values) {
        EXPECT_NEAR(v, p * upper, 1e-12 * upper) << p;
      }
      EXPECT_NEAR(refl.solver.depth((p * upper) * rw, upper), 0.0, 1e-9);
    }
    const NaturalSpectrum white = refl.solver.solve(upper * rw, upper);
    EXPECT_TRUE(white.converged);
    EXPECT_EQ(white.values, std::vector<double>(refl.grid.size(), upper));
  }
  for (double k : {1e-6, 1.0, 1e6}) {
    const NaturalSpectrum r = light.solver.solve(k * lw, kLight);
    ASSERT_TRUE(r.converged) << k;
    for (double v : r.values) {
      EXPECT_NEAR(v, k, 1e-12 * k);
    }
  }
}

TEST(NaturalSolver, TheBoundAndALightsBrightnessScaleTheSolution) {
  // L_u(z) = u L_1(z): the solution for (u t, u) is u times the one for (t, 1); a light's z + log
  // k is k times its spectrum with the same roughness: (k t) gives k x. 1e-9 relative.
  std::mt19937 rng(23);
  const OnGrid refl(true), light(false);
  for (int c = 0; c < 5; ++c) {
    const Xyz t = refl.colour(smooth_spectrum(rng, refl.grid.size(), true));
    const NaturalSpectrum one = refl.solver.solve(t, 1.0);
    for (double u : {0.25, 4.0}) {
      std::vector<double> scaled = one.values;
      for (double& v : scaled) v *= u;
      const NaturalSpectrum r = refl.solver.solve(u * t, u);
      ASSERT_TRUE(r.converged);
      EXPECT_LE(rel_err(r.values, scaled), 1e-9) << "upper " << u;
    }
    const Xyz l = light.colour(smooth_spectrum(rng, light.grid.size(), false));
    const NaturalSpectrum base = light.solver.solve(l, kLight);
    for (double k : {1e-4, 1e4}) {
      std::vector<double> scaled = base.values;
      for (double& v : scaled) v *= k;
      EXPECT_LE(rel_err(light.solver.solve(k * l, kLight).values, scaled), 1e-9) << "k " << k;
    }
  }
}

TEST(NaturalSolver, TargetsWithoutASolutionGetBoundedValuesAndNoConvergence) {
  // No exception, no hang (100 ms), values within the bounds and converged == false for what
  // no spectrum reproduces: NaN, infinite, black or negative luminance, brighter than white,
  // beyond the solid at a possible luminance; a bound <= 0; fewer than three samples.
  const OnGrid refl(true), light(false);
  const Xyz rw = refl.white();
  const double x0 = rw.X / rw.sum(), y0 = rw.Y / rw.sum();
  struct Case {
    const char* what;
    Xyz t;
    double upper;
  } cases[] = {{"NaN", {NAN, 0.5, 0.5}, 1.0},
               {"infinite", {INFINITY, 0.5, 0.5}, 1.0},
               {"black", {0, 0, 0}, 1.0},
               {"negative Y", {0.1, -0.1, 0.1}, 1.0},
               {"brighter than white", 1.5 * rw, 1.0},
               {"beyond the solid", xyz_from_xy(x0 + 0.3, y0 - 0.1, 0.5), 1.0},
               {"bound 0", 0.3 * rw, 0.0},
               {"bound -1", 0.3 * rw, -1.0}};
  for (const Case& c : cases) {
    SCOPED_TRACE(c.what);
    const NaturalSpectrum r = refl.solver.solve(c.t, c.upper);
    EXPECT_FALSE(r.converged);
    // It gives up within its stated cap (counted, not timed: no load can break it).
    EXPECT_LE(r.iterations, NaturalSolver::kMaxIterations);
    ASSERT_EQ(r.values.size(), refl.grid.size());
    for (double v : r.values) {
      EXPECT_GE(v, 0.0);
      EXPECT_LE(v, std::max(c.upper, 0.0));
    }
  }
  for (const Xyz& t : {Xyz{NAN, 1, 1}, Xyz{0, 0, 0}, Xyz{1, -1, 1}}) {
    const NaturalSpectrum r = light.solver.solve(t, kLight);
    EXPECT_FALSE(r.converged);
    for (double v : r.values) {
      EXPECT_EQ(v, 0.0);
    }
  }
  const std::vector<Xyz> two(refl.w.columns().begin(), refl.w.columns().begin() + 2);
  const NaturalSolver tiny(two, 5.0);
  const NaturalSpectrum r = tiny.solve(two[0] + two[1], kLight);
  EXPECT_FALSE(r.converged);
  EXPECT_EQ(r.values, std::vector<double>(2, 0.0));
}

TEST(NaturalSolver, DepthIsLinearAlongTheRayAndOneOnTheLocus) {
  // Lights: 0 on the equal-energy white's ray; linear along the ray from the white of the same
  // Y and independent of brightness (1e-9); a single wavelength's light at 450..560 nm (where
  // the sampled locus is strictly convex, so each sample is a vertex of it) is on the locus,
  // depth 1 (1e-9); +inf without luminance. Reflectances: +inf at Y <= 0 or at the white's
  // luminance and beyond.
  const OnGrid light(false), refl(true);
  const Xyz lw = light.white();
  EXPECT_NEAR(light.solver.depth(2.0 * lw, kLight), 0.0, 1e-12);
  for (std::size_t i = 4; i <= 76; i += 3) {
    std::vector<double> phi(light.grid.size(), 0.0);
    phi[i] = 1.0;
    const Xyz t = light.colour(phi);
    const Xyz centre = (t.Y / lw.Y) * lw;
    SCOPED_TRACE(std::to_string(light.grid[i]) + " nm");
    const double g = light.solver.depth(t, kLight);
    EXPECT_NEAR(light.solver.depth(1e5 * t, kLight), g, 1e-9 * g);
    for (double f : {0.25, 0.7}) {
      EXPECT_NEAR(light.solver.depth(centre + f * (t - centre), kLight), f * g, 1e-9 * g);
    }
    if (i >= 14 && i <= 36) {
      EXPECT_NEAR(g, 1.0, 1e-9);
    }
  }
  EXPECT_EQ(light.solver.depth({0.1, 0, 0.1}, kLight), INFINITY);
  EXPECT_EQ(light.solver.depth({0.1, -1, 0.1}, kLight), INFINITY);
  const Xyz rw = refl.white();
  EXPECT_EQ(refl.solver.depth(rw, 1.0), INFINITY);
  EXPECT_EQ(refl.solver.depth(1.2 * rw, 1.0), INFINITY);
  EXPECT_EQ(refl.solver.depth({0.1, 0, 0.1}, 1.0), INFINITY);
  EXPECT_LT(refl.solver.depth(0.99 * rw, 1.0), 1e-9);
}

TEST(NaturalSolver, FallbackWeightRisesLinearlyFromTheNaturalDepth) {
  // With the natural zone ending at depth 0.5: targets deeper take the fallback with weight
  // (g - 0.5) / (1 - 0.5), exact and bounded; shallower ones none. The default zone (0.999)
  // takes none at those depths.
  const OnGrid half(true, 0.5), standard(true);
  const Xyz rw = half.white();
  const double x0 = rw.X / rw.sum(), y0 = rw.Y / rw.sum();
  for (int h = 0; h < 6; ++h) {
    const double a = 2 * M_PI * h / 6;
    const Xyz grey = 0.3 * rw;
    const Xyz far = xyz_from_xy(x0 + 0.05 * std::cos(a), y0 + 0.05 * std::sin(a), 0.3);
    const double g_far = half.solver.depth(far, 1.0);
    ASSERT_TRUE(g_far > 0 && g_far < 1) << h;
    for (double g : {0.3, 0.6, 0.8, 0.95}) {
      const Xyz t = grey + (g / g_far) * (far - grey);
      SCOPED_TRACE("hue " + std::to_string(h) + " depth " + std::to_string(g));
      const NaturalSpectrum r = half.solver.solve(t, 1.0);
      ASSERT_TRUE(r.converged);
      EXPECT_LE(rel_err(half.colour(r.values), t), 1e-12);
      for (double v : r.values) {
        ASSERT_GT(v, 0.0);
        ASSERT_LT(v, 1.0);
      }
      EXPECT_EQ(r.fallback, g > 0.5);
      EXPECT_NEAR(r.fallback_weight, g > 0.5 ? (g - 0.5) / 0.5 : 0.0, 1e-9);
      const NaturalSpectrum d = standard.solver.solve(t, 1.0);
      EXPECT_FALSE(d.fallback);
      EXPECT_EQ(d.fallback_weight, 0.0);
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

TEST(NaturalSolver, FallbackIsContinuousAcrossItsThreshold) {
  // A gradient that crosses the natural zone's edge (depth 0.999) toward the gamut boundary,
  // walked in 30 and in 300 steps: a continuous path's largest step shrinks ~10x with the step,
  // a seam would keep its jump. Six Rec.2020 hues, both modes; the walk ends at depth 0.9995.
  for (Mode mode : {Mode::reflectance, Mode::emission}) {
    const Spectralizer sp = make(mode, "380:780:5", "cie1931", "D65", "natural");
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

TEST(NaturalSolver, DepthIsZeroOnTheGreyAndOneOnTheBoundary) {
  // The depth the fallback is decided by, against the gamut test of the Spectralizer: 0 on the
  // grey ray, 1 where in_gamut() flips (bisection, 1e-6), > 1 outside.
  const Spectralizer sp = make(Mode::reflectance, "380:780:5", "cie1931", "D65", "natural");
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
