// The bounded projection (core/bounded_projection.h): min ||x - start||^2 with W x = target and
// 0 <= x <= upper. The oracle is the problem's own optimality (KKT) conditions, checked by the
// test's own arithmetic: x = clamp(start + W^T nu) for one multiplier nu, fitted here by least
// squares on the free samples, and W x = target summed here.

#include "core/solvers/bounded_projection.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace spectralize {
namespace {

// Bell-shaped positive columns over 40 samples, like colour-matching functions on a grid.
std::vector<Xyz> columns() {
  std::vector<Xyz> w;
  for (int i = 0; i < 40; ++i) {
    const double t = i / 39.0;
    auto bell = [t](double mu, double s) { return std::exp(-0.5 * (t - mu) * (t - mu) / (s * s)); };
    w.push_back({0.35 * bell(0.75, 0.12) + 0.1 * bell(0.15, 0.06), bell(0.55, 0.12),
                 1.2 * bell(0.2, 0.09)});
  }
  return w;
}

Xyz image(const std::vector<Xyz>& w, const std::vector<double>& x) {
  Xyz sum;
  for (std::size_t i = 0; i < w.size(); ++i) sum = sum + x[i] * w[i];
  return sum;
}

double relative(const Xyz& a, const Xyz& b) {
  return (a - b).max_abs() / std::max(b.max_abs(), 1e-300);
}

// nu by least squares from the free samples (x_i - start_i = W_i . nu there), then the signs the
// clamp requires of the bounded ones. Returns the largest violation, relative to max |start|.
double kkt_violation(const std::vector<Xyz>& w, const std::vector<double>& start,
                     const std::vector<double>& x, double upper) {
  double a[3][3] = {}, b[3] = {};
  for (std::size_t i = 0; i < w.size(); ++i) {
    if (x[i] <= 1e-12 || x[i] >= upper - 1e-12) continue;
    for (int r = 0; r < 3; ++r) {
      b[r] += w[i][r] * (x[i] - start[i]);
      for (int c = 0; c < 3; ++c) a[r][c] += w[i][r] * w[i][c];
    }
  }
  // Cramer's rule on the 3x3 normal equations.
  auto det = [](double m[3][3]) {
    return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
           m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  };
  const double d = det(a);
  double nu[3];
  for (int k = 0; k < 3; ++k) {
    double m[3][3];
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) m[r][c] = c == k ? b[r] : a[r][c];
    nu[k] = det(m) / d;
  }
  double worst = 0;
  for (std::size_t i = 0; i < w.size(); ++i) {
    const double z = start[i] + w[i][0] * nu[0] + w[i][1] * nu[1] + w[i][2] * nu[2];
    worst = std::max(worst, std::abs(std::clamp(z, 0.0, upper) - x[i]));
  }
  return worst;
}

TEST(BoundedProjection, MeetsTheOptimalityConditionsAndTheTarget) {
  const auto w = columns();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int k = 0; k < 200; ++k) {
    // A target made by a bounded spectrum (so feasible), and an unrelated start outside bounds.
    std::vector<double> made(w.size()), start(w.size());
    for (auto& v : made) v = u(rng);
    for (auto& v : start) v = 1.6 * u(rng) - 0.3;
    const Xyz target = image(w, made);
    const Projection p = project_exact(w, start, target, 1.0);
    ASSERT_TRUE(p.converged) << k;
    EXPECT_LE(relative(image(w, p.values), target), 1e-12) << k;
    EXPECT_NEAR(p.residual, relative(image(w, p.values), target), 1e-15) << k;
    for (double v : p.values) {
      EXPECT_GE(v, 0.0);
      EXPECT_LE(v, 1.0);
    }
    EXPECT_LT(kkt_violation(w, start, p.values, 1.0), 1e-9) << k;
  }
}

TEST(BoundedProjection, AnExactBoundedSpectrumIsItsOwnProjection) {
  const auto w = columns();
  std::vector<double> x(w.size());
  for (std::size_t i = 0; i < x.size(); ++i)
    x[i] = 0.2 + 0.6 * std::sin(0.3 * i) * std::sin(0.3 * i);
  const Projection p = project_exact(w, x, image(w, x), 1.0);
  ASSERT_TRUE(p.converged);
  EXPECT_EQ(p.iterations, 0);
  for (std::size_t i = 0; i < x.size(); ++i) {
    EXPECT_DOUBLE_EQ(p.values[i], x[i]);
  }
}

// The control: a looser tolerance stops sooner (never later) and keeps its promise; an
// infeasible target (brighter than the perfect reflector) is reported, within the cap.
TEST(BoundedProjection, TheControlSetsWhereItStops) {
  const auto w = columns();
  std::vector<double> ones(w.size(), 1.0), start(w.size(), 0.0);
  const Xyz target = 0.5 * image(w, ones) + Xyz{0.01, 0, 0};
  const Projection tight = project_exact(w, start, target, 1.0);
  const Projection loose = project_exact(w, start, target, 1.0, {1e-4, 1e-12, 500});
  ASSERT_TRUE(tight.converged);
  ASSERT_TRUE(loose.converged);
  EXPECT_LE(loose.iterations, tight.iterations);
  EXPECT_LE(relative(image(w, loose.values), target), 1e-4);
  const Projection capped = project_exact(w, start, 2.0 * image(w, ones), 1.0, {1e-13, 1e-12, 7});
  EXPECT_FALSE(capped.converged);
  EXPECT_LE(capped.iterations, 7);
  // No bounded spectrum is brighter than the perfect reflector: at best half the target.
  EXPECT_GE(capped.residual, 0.5 - 1e-12);
}

TEST(BoundedProjection, PolishKeepsZerosAndReachesTheTarget) {
  const auto w = columns();
  std::vector<double> x(w.size(), 0.4);
  for (std::size_t i = 0; i < 8; ++i) x[i] = 0;
  const Xyz target = 1.01 * image(w, x) + Xyz{0, 0.001, 0};
  std::vector<double> polished = x;
  ASSERT_TRUE(polish_exact(w, polished, target));
  EXPECT_LE(relative(image(w, polished), target), 1e-12);
  for (std::size_t i = 0; i < 8; ++i) {
    EXPECT_EQ(polished[i], 0.0);
  }
}

}  // namespace
}  // namespace spectralize
