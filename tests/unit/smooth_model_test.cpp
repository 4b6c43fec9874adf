// SmoothModel (src/core/models/smooth_model.h, docs/DESIGN.md §6): the least-roughness exact
// bounded spectrum for the context's curvature length tau. Each tau's spectrum is the smoothest by
// its own measure (no rougher by it than another tau's spectrum of the same colour, which is as
// exact and bounded); its details are its iterations and whether the primal phase ran; near
// the locus, where the fast phase may fail, the spectrum is still exact and bounded. Exactness
// by the test's own integration (test_support.h).

#include "core/models/smooth_model.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "spectralize/core/sample_weights.h"
#include "test_support.h"

namespace spectralize {
namespace {

using test::reference_xyz;
using test::rel_err;

struct OnGrid : test::DefaultGridWeights {
  std::vector<double> nm = wavelengths();
  explicit OnGrid(bool refl) : DefaultGridWeights(refl) {}
  ModelContext context(double tau) const {
    ModelContext c;
    c.columns = w.columns();
    c.wavelengths = nm;
    c.step_nm = grid.step();
    c.curvature_nm = tau;
    return c;
  }
};

TEST(SmoothModel, EachCurvatureLengthGivesTheSmoothestSpectrumByItsOwnMeasure) {
  // tau = 0 (slope only), 50 nm (the default) and 150 nm on random reflectances' colours: each
  // spectrum is exact (1e-12) and within [0, 1], no rougher by its own tau's measure
  // (SmoothSolver::roughness of Roughness::of_length(tau, 5)) than the others', and the
  // spectra differ (tau is used).
  const OnGrid g(true);
  const std::vector<double> taus = {0.0, 50.0, 150.0};
  std::vector<SmoothModel> models;
  std::vector<SmoothSolver> measures;
  for (double tau : taus) {
    models.emplace_back(g.context(tau));
    measures.emplace_back(g.w.columns(), Roughness::of_length(tau, 5.0));
  }
  std::mt19937 rng(37);
  std::uniform_real_distribution<double> u(0.05, 0.95);
  for (int k = 0; k < 20; ++k) {
    std::vector<double> rho(g.grid.size());
    const double a = u(rng), b = u(rng);
    for (std::size_t i = 0; i < rho.size(); ++i)
      rho[i] = a + (b - a) * std::pow(static_cast<double>(i) / 80.0, 3) * (0.9 + 0.1 * u(rng));
    const Xyz t = g.colour(rho);
    std::vector<std::vector<double>> x;
    for (const SmoothModel& m : models) {
      const ModelSolution s = m.solve(t, 1.0);
      ASSERT_TRUE(s.converged) << k;
      EXPECT_LE(rel_err(g.colour(s.values), t), 1e-12);
      for (double v : s.values) {
        ASSERT_GE(v, 0.0);
        ASSERT_LE(v, 1.0);
      }
      x.push_back(s.values);
    }
    for (std::size_t p = 0; p < taus.size(); ++p)
      for (std::size_t q = 0; q < taus.size(); ++q) {
        EXPECT_LE(measures[p].roughness(x[p]), measures[p].roughness(x[q]) * (1 + 1e-9) + 1e-15)
            << "colour " << k << ": tau " << taus[p] << " against tau " << taus[q];
      }
    EXPECT_GT(rel_err(x[0], x[2]), 1e-3) << k;
  }
}

TEST(SmoothModel, DetailsAreItsIterationsAndWhetherThePrimalPhaseRan) {
  const OnGrid g(false);
  const SmoothModel model(g.context(50));
  const ModelSolution s = model.solve(g.colour(std::vector<double>(g.grid.size(), 0.4)), INFINITY);
  ASSERT_TRUE(s.converged);
  ASSERT_EQ(s.details.size(), 2u);
  EXPECT_EQ(s.details[0].name, "iterations");
  EXPECT_FALSE(s.details[0].boolean);
  EXPECT_GE(s.details[0].value, 1.0);
  EXPECT_EQ(s.details[1].name, "primal_phase");
  EXPECT_TRUE(s.details[1].boolean);
  EXPECT_EQ(s.details[1].value, s.fallback ? 1.0 : 0.0);
  EXPECT_FALSE(s.fallback);  // a grey light: the fast phase suffices
}

TEST(SmoothModel, ColoursHuggingTheLocusAreBoundedAndExactWhereItSaysSo) {
  // Two-sample lights and reflectances (the locus' edges) moved 1e-6 of the way toward the
  // equal-energy white, as the gamut mapping leaves colours outside the locus (docs/DESIGN.md
  // §5), where the fast phase may cycle and the model restarts from the paper model's
  // spectrum (reported as primal_phase): always within the bounds; exact (1e-9) wherever it
  // reports convergence, which it does for every light and all but one reflectance (the
  // violet end's first edge, where the Spectralizer's own fallback makes it exact).
  for (bool reflectance : {false, true}) {
    const OnGrid g(reflectance);
    const SmoothModel model(g.context(50));
    const std::size_t n = g.grid.size();
    const Xyz white = g.colour(std::vector<double>(n, 1.0));
    const double upper = reflectance ? 1.0 : INFINITY;
    int primal = 0, unconverged = 0;
    for (std::size_t i = 0; i + 1 < n; i += 2) {
      std::vector<double> phi(n, 0.0);
      phi[i] = phi[i + 1] = reflectance ? 0.5 : 1.0;
      const Xyz edge = g.colour(phi);
      const Xyz t = edge + 1e-6 * ((edge.Y / white.Y) * white - edge);
      const ModelSolution s = model.solve(t, upper);
      for (double v : s.values) {
        ASSERT_GE(v, 0.0);
        ASSERT_LE(v, upper);
      }
      if (s.converged) {
        EXPECT_LE(rel_err(g.colour(s.values), t), 1e-9) << g.grid[i] << " nm";
      } else {
        ++unconverged;
      }
      primal += s.fallback;
      EXPECT_EQ(s.details[1].value, s.fallback ? 1.0 : 0.0);
    }
    std::printf("  %s: %d of %zu used the primal phase, %d unconverged\n",
                reflectance ? "reflectance" : "emission", primal, n / 2, unconverged);
    EXPECT_LE(unconverged, reflectance ? 1 : 0);
  }
}

}  // namespace
}  // namespace spectralize
