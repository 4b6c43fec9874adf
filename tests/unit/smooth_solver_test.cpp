// SmoothSolver (src/core/solvers/smooth_solver.h, docs/DESIGN.md §6): the least-roughness spectrum
// among the exact ones within 0 <= x <= upper. The roughness is checked against its definition
// (weighted squared first and second differences), the solutions for exactness (the test's own
// integration, test_support.h), bounds and optimality: no feasible direction (a move of the
// free samples in the null space of W, or a bound sample moved inward and compensated on the
// free ones) lowers the roughness, its gradient written out here. Targets are the colours of
// known spectra (feasible by construction), which the solution may not be rougher than.

#include "core/solvers/smooth_solver.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "spectralize/core/sample_weights.h"
#include "spectralize/core/spectralizer.h"
#include "test_support.h"

namespace spectralize {
namespace {

using test::inverse;
using test::Mat3;
using test::mul;
using test::reference_xyz;
using test::rel_err;

constexpr double kLight = std::numeric_limits<double>::infinity();

using OnGrid = test::DefaultGridWeights;

// The roughness of the definition and its gradient, written out.
double roughness_of(const std::vector<double>& x, const Roughness& r) {
  double sum = 0;
  for (std::size_t i = 0; i + 1 < x.size(); ++i) sum += r.slope * std::pow(x[i + 1] - x[i], 2);
  for (std::size_t i = 0; i + 2 < x.size(); ++i)
    sum += r.curvature * std::pow(x[i] - 2 * x[i + 1] + x[i + 2], 2);
  return sum;
}
std::vector<double> gradient_of(const std::vector<double>& x, const Roughness& r) {
  std::vector<double> g(x.size(), 0.0);
  for (std::size_t i = 0; i + 1 < x.size(); ++i) {
    const double d = 2 * r.slope * (x[i + 1] - x[i]);
    g[i] -= d;
    g[i + 1] += d;
  }
  for (std::size_t i = 0; i + 2 < x.size(); ++i) {
    const double d = 2 * r.curvature * (x[i] - 2 * x[i + 1] + x[i + 2]);
    g[i] += d;
    g[i + 1] -= 2 * d;
    g[i + 2] += d;
  }
  return g;
}

// The largest decrease rate of the roughness along a feasible direction of unit length,
// relative to |gradient|: for each free sample set F (strictly inside the bounds by 1e-9 of
// the spectrum), directions in {d : W d = 0, d = 0 off F} (both signs), and for each sample on
// a bound, the move inward compensated on F by least norm. 0 (to rounding) at the optimum.
double worst_descent(const std::vector<Xyz>& c, const std::vector<double>& x, double upper,
                     const Roughness& r, std::mt19937& rng) {
  const std::size_t n = x.size();
  const std::vector<double> g = gradient_of(x, r);
  double top = 0, gnorm = 0;
  for (double v : x) top = std::max(top, v);
  for (double v : g) gnorm += v * v;
  gnorm = std::sqrt(gnorm);
  if (!(gnorm > 0)) return 0;
  const double eps = 1e-9 * top;
  std::vector<bool> free(n);
  Mat3 a{};
  for (std::size_t i = 0; i < n; ++i) {
    free[i] = x[i] > eps && x[i] < upper - eps;
    if (!free[i]) continue;
    for (int p = 0; p < 3; ++p)
      for (int q = 0; q < 3; ++q) a[p][q] += c[i][p] * c[i][q];
  }
  const Mat3 ainv = inverse(a);
  // Removes from d (on F) its component outside the null space of W_F, after adding `fixed`
  // (the colour the rest of d makes, to be compensated).
  auto compensate = [&](std::vector<double>& d, Xyz fixed) {
    for (std::size_t i = 0; i < n; ++i)
      if (free[i]) fixed = fixed + d[i] * c[i];
    const Xyz m = mul(ainv, fixed);
    for (std::size_t i = 0; i < n; ++i)
      if (free[i]) d[i] -= dot(c[i], m);
  };
  auto rate = [&](const std::vector<double>& d) {
    double gd = 0, dd = 0;
    for (std::size_t i = 0; i < n; ++i) gd += g[i] * d[i], dd += d[i] * d[i];
    return dd > 0 ? -gd / std::sqrt(dd) / gnorm : 0.0;
  };
  double worst = 0;
  std::normal_distribution<double> normal;
  for (int k = 0; k < 20; ++k) {
    std::vector<double> d(n, 0.0);
    for (std::size_t i = 0; i < n; ++i)
      if (free[i]) d[i] = normal(rng);
    compensate(d, Xyz{});
    worst = std::max({worst, rate(d), -rate(d)});  // both signs are feasible
  }
  for (std::size_t j = 0; j < n; ++j) {
    if (free[j]) continue;
    std::vector<double> d(n, 0.0);
    d[j] = x[j] <= eps ? 1.0 : -1.0;  // inward
    compensate(d, d[j] * c[j]);
    worst = std::max(worst, rate(d));
  }
  return worst;
}

// A random target's source: smooth, rough or saturated (blocks at the bounds), in [0, 1].
std::vector<double> source_spectrum(std::mt19937& rng, std::size_t n, int kind) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<double> s(n);
  const double p1 = 6 * u(rng), p2 = 6 * u(rng), f = 0.5 + 2 * u(rng);
  const double centre = 0.3 + 0.4 * u(rng), half = 0.08 + 0.15 * u(rng);
  for (std::size_t i = 0; i < n; ++i) {
    const double t = static_cast<double>(i) / static_cast<double>(n - 1);
    switch (kind) {
      case 0:  // smooth
        s[i] = 0.5 + 0.3 * std::sin(f * 3 * t + p1) + 0.1 * std::cos(7 * t + p2);
        break;
      case 1:  // rough
        s[i] = 0.1 + 0.8 * u(rng);
        break;
      default:  // saturated: a band near 1 between two near 0
        s[i] = std::abs(t - centre) < half ? 0.999 : 0.002;
        break;
    }
  }
  return s;
}

TEST(SmoothSolver, RoughnessIsTheWeightedSumOfSquaredDifferences) {
  // of_length(tau, h) is the discrete integral of x'^2 + tau^2 x''^2 over nm, scaled by h:
  // slope 1 and curvature (tau / h)^2.
  EXPECT_EQ(Roughness::of_length(50, 5).slope, 1.0);
  EXPECT_EQ(Roughness::of_length(50, 5).curvature, 100.0);
  EXPECT_EQ(Roughness::of_length(10, 1).curvature, 100.0);
  EXPECT_EQ(Roughness::of_length(5, 10).curvature, 0.25);
  const OnGrid s(true);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 2.0);
  const std::size_t n = s.grid.size();
  for (const Roughness r :
       {Roughness{1, 0}, Roughness{0, 1}, Roughness{2.5, 3}, Roughness::of_length(50, 5)}) {
    SCOPED_TRACE(std::to_string(r.slope) + ", " + std::to_string(r.curvature));
    const SmoothSolver solver(s.w.columns(), r);
    EXPECT_EQ(solver.size(), n);
    std::vector<double> x(n);
    for (double& v : x) v = u(rng);
    const double want = roughness_of(x, r);
    EXPECT_NEAR(solver.roughness(x), want, 1e-12 * want);
    // Constants: zero, to the rounding of the sum (1e-12 of its terms' size).
    EXPECT_NEAR(solver.roughness(std::vector<double>(n, 0.7)), 0.0,
                1e-12 * (r.slope + r.curvature) * n);
    std::vector<double> ramp(n);
    for (std::size_t i = 0; i < n; ++i) ramp[i] = 0.01 * static_cast<double>(i);
    // A ramp has no second differences: only the slope term, (N - 1) x 0.01^2.
    EXPECT_NEAR(solver.roughness(ramp), r.slope * 80 * 1e-4, 1e-12 * (r.slope + r.curvature) * n);
  }
}

TEST(SmoothSolver, SolutionsAreExactBoundedOptimalAndNoRougherThanTheirSource) {
  // Targets: the colours of smooth, rough and saturated source spectra (so feasible), as
  // reflectances (bounds 1 and 2) and lights, with the model's roughness and a slope-only one.
  // Exact to 1e-12 by the test's integration, within the bounds, no feasible descent direction
  // (1e-6 of the gradient's scale: the solver's tiny ridge), and no rougher than the source.
  std::mt19937 rng(29);
  for (bool reflectance : {true, false}) {
    const OnGrid s(reflectance);
    const std::vector<Xyz> c(s.w.columns().begin(), s.w.columns().end());
    for (const Roughness r : {Roughness::of_length(50, 5), Roughness{1, 0}}) {
      const SmoothSolver solver(s.w.columns(), r);
      for (double upper :
           reflectance ? std::vector<double>{1.0, 2.0} : std::vector<double>{kLight}) {
        SCOPED_TRACE(std::string(reflectance ? "reflectance" : "emission") + " upper " +
                     std::to_string(upper) + " curvature " + std::to_string(r.curvature));
        int active = 0;
        for (int k = 0; k < 45; ++k) {
          std::vector<double> source = source_spectrum(rng, s.grid.size(), k % 3);
          if (std::isfinite(upper))
            for (double& v : source) v *= upper;
          const Xyz t = s.colour(source);
          const SmoothSpectrum x = solver.solve(t, upper);
          ASSERT_TRUE(x.converged) << k;
          EXPECT_LE(rel_err(s.colour(x.values), t), 1e-12) << k;
          bool bound = false;
          for (double v : x.values) {
            ASSERT_GE(v, 0.0);
            ASSERT_LE(v, upper);
            bound |= v == 0.0 || v == upper;
          }
          active += bound;
          EXPECT_LE(worst_descent(c, x.values, upper, r, rng), 1e-6) << k;
          EXPECT_LE(roughness_of(x.values, r), roughness_of(source, r) * (1 + 1e-9)) << k;
        }
        EXPECT_GT(active, 5);  // the bounds were active for some: the active set was exercised
      }
    }
  }
}

TEST(SmoothSolver, GreysAreFlatAndACurvatureOnlyRoughnessKeepsARamp) {
  // Constants (and, without the slope term, straight lines) have zero roughness: a grey's
  // solution is flat, and a ramp's colour gives back the ramp when only curvature counts (the
  // unique exact spectrum of zero roughness); 1e-6 relative (the ridge).
  const OnGrid s(true);
  const std::size_t n = s.grid.size();
  const SmoothSolver slope(s.w.columns(), Roughness{1, 0});
  const SmoothSolver model(s.w.columns(), Roughness::of_length(50, 5));
  for (double p : {0.05, 0.5, 0.95}) {
    const Xyz t = s.colour(std::vector<double>(n, p));
    for (const SmoothSolver* solver : {&slope, &model}) {
      const SmoothSpectrum x = solver->solve(t, 1.0);
      ASSERT_TRUE(x.converged);
      for (double v : x.values) {
        EXPECT_NEAR(v, p, 1e-6 * p);
      }
    }
  }
  const SmoothSolver curvature(s.w.columns(), Roughness{0, 1});
  std::vector<double> ramp(n);
  for (std::size_t i = 0; i < n; ++i) ramp[i] = 0.2 + 0.6 * static_cast<double>(i) / (n - 1.0);
  const SmoothSpectrum x = curvature.solve(s.colour(ramp), 1.0);
  ASSERT_TRUE(x.converged);
  EXPECT_LE(rel_err(x.values, ramp), 1e-6);
  // The slope term does not keep it: the ramp is not the least-slope spectrum of its colour.
  const SmoothSpectrum y = slope.solve(s.colour(ramp), 1.0);
  EXPECT_GT(rel_err(y.values, ramp), 1e-3);
  EXPECT_LT(roughness_of(y.values, {1, 0}), roughness_of(ramp, {1, 0}));
}

TEST(SmoothSolver, BlackIsZeroAndALightScalesWithItsColour) {
  // x^T H x is homogeneous of degree 2 and unbounded above for lights: (k t) gives k x
  // (1e-9 relative); black is the zero spectrum.
  const OnGrid s(false);
  const SmoothSolver solver(s.w.columns(), Roughness::of_length(50, 5));
  const SmoothSpectrum black = solver.solve({0, 0, 0});
  EXPECT_TRUE(black.converged);
  EXPECT_EQ(black.values, std::vector<double>(s.grid.size(), 0.0));
  std::mt19937 rng(31);
  const Xyz t = s.colour(source_spectrum(rng, s.grid.size(), 0));
  const SmoothSpectrum base = solver.solve(t);
  for (double k : {1e-5, 1e5}) {
    std::vector<double> scaled = base.values;
    for (double& v : scaled) v *= k;
    EXPECT_LE(rel_err(solver.solve(k * t).values, scaled), 1e-9) << k;
  }
  // The columns are the ones given.
  ASSERT_EQ(solver.columns().size(), s.grid.size());
  for (std::size_t i = 0; i < s.grid.size(); ++i) {
    EXPECT_EQ(solver.columns()[i], s.w.columns()[i]);
  }
}

TEST(SmoothSolver, TooFewSamplesGiveBoundedValuesAndNoConvergence) {
  // Two samples cannot meet three equations in general: no exception, within the bounds,
  // converged == false.
  const OnGrid s(true);
  const std::vector<Xyz> two = {s.w.columns()[20], s.w.columns()[50]};
  const SmoothSolver solver(two, Roughness{1, 0});
  const SmoothSpectrum x = solver.solve(s.w.columns()[30], 1.0);
  EXPECT_FALSE(x.converged);
  ASSERT_EQ(x.values.size(), 2u);
  for (double v : x.values) {
    EXPECT_GE(v, 0.0);
    EXPECT_LE(v, 1.0);
  }
}

TEST(SmoothSolver, SolverStopsOnAnInfeasibleTarget) {
  // Called directly with a target no reflectance has (brighter than white), the solver must
  // still return, within its iteration cap, with bounded values and converged == false.
  SpectralizerSettings s;
  s.mode = Mode::reflectance;
  const Spectralizer sp(s);
  const SmoothSolver solver(sp.weights().columns(), Roughness::of_length(50, 5));
  const SmoothSpectrum r = solver.solve(2.0 * sp.reference_white(), 1.0);
  EXPECT_FALSE(r.converged);
  // Within its stated cap (counted, not timed), the projection that found no start included.
  EXPECT_LE(r.iterations,
            SmoothSolver::max_iterations(static_cast<int>(sp.weights().columns().size())));
  for (double v : r.values) {
    EXPECT_GE(v, 0.0);
    EXPECT_LE(v, 1.0);
  }
}

}  // namespace
}  // namespace spectralize
