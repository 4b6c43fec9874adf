// PaperModel (src/core/models/paper_model.h, docs/DESIGN.md §2, §6): the paper's filtered average
// made exact and bounded. Its details count the admissible and dropped partial solutions (the drop
// rule written out here); an average above the bound is replaced by the exact projection within
// it, reported as bounded; edge peaks the automatic filter's ladder leaves are capped exactly,
// reported as edge_capped. Exactness by the test's own integration (test_support.h).

#include "core/models/paper_model.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "spectralize/core/sample_weights.h"
#include "spectralize/core/spectralizer.h"
#include "spectralizer_checks.h"
#include "test_support.h"

namespace spectralize {
namespace {

using namespace test;  // NOLINT: the checks of spectralizer_checks.h

// A model context on the default grid (reflectance under D65, or emission).
struct OnGrid : test::DefaultGridWeights {
  std::vector<double> nm = wavelengths();
  explicit OnGrid(bool refl) : DefaultGridWeights(refl) {}
  ModelContext context(const EdgeFilter& filter) const {
    ModelContext c;
    c.columns = w.columns();
    c.wavelengths = nm;
    c.step_nm = grid.step();
    c.filter = filter;
    return c;
  }
};

double detail(const ModelSolution& s, const std::string& name) {
  for (const ModelDetail& d : s.details)
    if (d.name == name) return d.value;
  ADD_FAILURE() << "no detail " << name;
  return NAN;
}

TEST(PaperModel, DetailsCountTheAdmissibleAndDroppedPartialSolutions) {
  // Half of the L admissible partial solutions dropped: dropped = floor(L / 2); the details in
  // their print order, the flags as booleans; the spectrum exact (1e-12) and non-negative.
  for (bool reflectance : {true, false}) {
    SCOPED_TRACE(reflectance ? "reflectance" : "emission");
    const OnGrid g(reflectance);
    const PaperModel model(g.context(EdgeFilter::fraction(0.5)));
    const double upper = reflectance ? 1.0 : INFINITY;
    for (double level : {0.2, 0.6}) {
      const Xyz t = level * g.colour(std::vector<double>(g.grid.size(), 0.8));
      const ModelSolution s = model.solve(t, upper);
      ASSERT_TRUE(s.converged);
      ASSERT_EQ(s.details.size(), 4u);
      EXPECT_EQ(s.details[0].name, "admissible");
      EXPECT_EQ(s.details[1].name, "dropped");
      EXPECT_EQ(s.details[2].name, "bounded");
      EXPECT_EQ(s.details[3].name, "edge_capped");
      EXPECT_FALSE(s.details[0].boolean || s.details[1].boolean);
      EXPECT_TRUE(s.details[2].boolean && s.details[3].boolean);
      const double admissible = detail(s, "admissible");
      EXPECT_GT(admissible, 1000);  // a grey is inside most triangles of samples
      EXPECT_EQ(detail(s, "dropped"), std::floor(admissible / 2));
      EXPECT_EQ(detail(s, "edge_capped"), 0.0);  // a fixed fraction never caps
      EXPECT_LE(rel_err(g.colour(s.values), t), 1e-12);
      for (double v : s.values) {
        EXPECT_GE(v, 0.0);
      }
    }
  }
}

TEST(PaperModel, AnAverageAboveTheBoundIsProjectedExactlyWithinIt) {
  // A grey of 30%: under a bound twice its average's largest sample nothing is projected (the
  // average itself, exact); under half that sample the exact projection brings it within the
  // bound, exact (1e-12), and says so (bounded, fallback).
  const OnGrid g(true);
  const PaperModel model(g.context(EdgeFilter::fraction(0.7)));
  const Xyz t = g.colour(std::vector<double>(g.grid.size(), 0.3));
  const ModelSolution loose = model.solve(t, 1e6);
  ASSERT_TRUE(loose.converged);
  const double peak = *std::max_element(loose.values.begin(), loose.values.end());
  const ModelSolution free = model.solve(t, 2 * peak);
  ASSERT_TRUE(free.converged);
  EXPECT_EQ(detail(free, "bounded"), 0.0);
  EXPECT_FALSE(free.fallback);
  EXPECT_EQ(free.values, loose.values);
  const ModelSolution capped = model.solve(t, 0.5 * peak);
  ASSERT_TRUE(capped.converged);
  EXPECT_EQ(detail(capped, "bounded"), 1.0);
  EXPECT_TRUE(capped.fallback);
  for (double v : capped.values) {
    EXPECT_GE(v, 0.0);
    EXPECT_LE(v, 0.5 * peak);
  }
  EXPECT_LE(rel_err(g.colour(capped.values), t), 1e-12);
}

TEST(PaperModel, EdgePeaksTheLadderLeavesAreCappedExactly) {
  // A saturated red outside sRGB (xy 0.6754, 0.2391) keeps an edge peak even after dropping 99%
  // of the partial solutions; the automatic filter then caps the edge bands by the exact
  // projection: still exact (1e-9, double precision with margin) and non-negative, peak-free.
  const Spectralizer sp = make(Mode::emission);
  const Reference ref = reference_of(sp);
  const double x = 0.6754, y = 0.2391;
  const Xyz xyz{x / y, 1.0, (1 - x - y) / y};
  const SpectrumResult r = sp.spectralize(xyz);
  ASSERT_EQ(r.status, Outcome::exact);
  EXPECT_TRUE(r.detail("edge_capped"));
  EXPECT_LE(edge_peak_ratio(sp.settings().grid, r.values), 1.0);
  for (double v : r.values) {
    EXPECT_GE(v, 0.0);
  }
  EXPECT_LE(rel_err(integrate(sp, ref, r.values), xyz), 1e-9);
  // With an explicit filter the user's K is respected: no capping, the peak stays.
  SpectralizerSettings s = sp.settings();
  s.filter = EdgeFilter::fraction(0.99);
  const SpectrumResult plain = Spectralizer(s).spectralize(xyz);
  EXPECT_FALSE(plain.detail("edge_capped"));
  EXPECT_GT(edge_peak_ratio(s.grid, plain.values), 1.0);
}

}  // namespace
}  // namespace spectralize
