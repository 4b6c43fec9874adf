// PaperSolver against an independent brute force of the paper's method (docs/DESIGN.md §2):
// every triple i < j < k, its 3x3 system solved by Cramer's rule, the admissible (all densities
// >= 0) partial solutions averaged, optionally after dropping the K with the largest density
// (EdgeFilter itself is in edge_filter_test.cpp).

#include "core/solvers/paper_solver.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <random>
#include <vector>

#include "spectralize/core/edge_filter.h"
#include "spectralize/core/sample_weights.h"
#include "test_support.h"

namespace spectralize {
namespace {

using test::Mat3;
using test::rel_err;

// --- The brute-force reference ---

struct Partial {
  double max_density;
  std::size_t idx[3];
  double density[3];
};

// All admissible partial solutions: every triple i < j < k, Cramer's rule, all densities >= 0.
std::vector<Partial> brute_force_partials(const std::vector<Xyz>& c, const Xyz& t) {
  std::vector<Partial> out;
  const std::size_t n = c.size();
  auto col_matrix = [](const Xyz& a, const Xyz& b, const Xyz& d) {
    return Mat3{{{a.X, b.X, d.X}, {a.Y, b.Y, d.Y}, {a.Z, b.Z, d.Z}}};
  };
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j)
      for (std::size_t k = j + 1; k < n; ++k) {
        const double det = test::det3(col_matrix(c[i], c[j], c[k]));
        if (det == 0) continue;  // no unique partial solution
        const double a = test::det3(col_matrix(t, c[j], c[k])) / det;
        const double b = test::det3(col_matrix(c[i], t, c[k])) / det;
        const double d = test::det3(col_matrix(c[i], c[j], t)) / det;
        if (a >= 0 && b >= 0 && d >= 0) out.push_back({std::max({a, b, d}), {i, j, k}, {a, b, d}});
      }
  return out;
}

// Sum of the given partial solutions as a spectrum of n samples.
std::vector<double> sum_of(const std::vector<Partial>& parts, std::size_t n, std::size_t count) {
  std::vector<double> s(n, 0.0);
  for (std::size_t m = 0; m < count; ++m)
    for (int v = 0; v < 3; ++v) s[parts[m].idx[v]] += parts[m].density[v];
  return s;
}

struct Brute {
  std::size_t admissible = 0, kept = 0;
  std::vector<double> sum, average;
};

// The paper's average after dropping the `drop_fraction` * L partial solutions with the
// largest density (floor, keeping at least one): the reference for EdgeFilter::fraction.
Brute brute_force(const std::vector<Xyz>& c, const Xyz& t, double drop_fraction) {
  std::vector<Partial> parts = brute_force_partials(c, t);
  Brute b;
  b.admissible = parts.size();
  b.sum = sum_of(parts, c.size(), parts.size());
  std::size_t drop =
      static_cast<std::size_t>(std::floor(drop_fraction * static_cast<double>(parts.size())));
  if (parts.size() > 0 && drop >= parts.size()) drop = parts.size() - 1;
  b.kept = parts.size() - drop;
  std::sort(parts.begin(), parts.end(),
            [](const Partial& x, const Partial& y) { return x.max_density < y.max_density; });
  b.average = sum_of(parts, c.size(), b.kept);
  if (b.kept > 0)
    for (double& v : b.average) v /= static_cast<double>(b.kept);
  return b;
}

// Emission colours: the paper's light and surface, white, a few saturated and random ones.
std::vector<Xyz> emission_colours(std::size_t random_count, unsigned seed) {
  using test::kRec709ToXyz;
  std::vector<Xyz> out = {
      test::rgb(kRec709ToXyz, 6000, 5000, 1000), test::rgb(kRec709ToXyz, 0.21, 0.72, 0.15),
      test::rgb(kRec709ToXyz, 1, 1, 1),          test::rgb(kRec709ToXyz, 0.05, 0.9, 0.1),
      test::rgb(kRec709ToXyz, 0.2, 0.4, 0.9),    test::xyz_from_xy(0.6, 0.3, 0.5),
  };
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (std::size_t i = 0; i < random_count; ++i)
    out.push_back(test::rgb(kRec709ToXyz, u(rng), u(rng), u(rng)));
  return out;
}

// Compares solver and brute force for the given weights and targets; prints the worst
// deviations seen (for the record, not asserted beyond the tolerances below).
void compare_with_brute_force(const std::vector<Xyz>& w, const std::vector<Xyz>& targets) {
  struct {
    double sum = 0, filtered = 0, exact = 0;
    long dl = 0;
  } worst;
  PaperSolver solver(w);
  const std::size_t n = w.size();
  for (std::size_t ci = 0; ci < targets.size(); ++ci) {
    const Xyz& t = targets[ci];
    SCOPED_TRACE(::testing::Message()
                 << "colour " << ci << " XYZ (" << t.X << ", " << t.Y << ", " << t.Z << ")");
    const Brute ref = brute_force(w, t, 0.7);
    ASSERT_GT(ref.admissible, 0u);

    // Unfiltered: L and the sum. Both enumerate the same triples; they can disagree only on
    // triples whose target sits on a triangle edge (a density of exactly 0, decided by
    // rounding in either method), so |dL| <= 2. Sums to 1e-6 of their largest value: a
    // boundary triple contributes ~0 at its zero density, and rounding is ~1e-13.
    std::vector<double> sum(n);
    const std::size_t L = solver.sum_admissible(t, sum);
    EXPECT_LE(std::abs(static_cast<long>(L) - static_cast<long>(ref.admissible)), 2)
        << "solver L " << L << " brute L " << ref.admissible;
    EXPECT_LE(rel_err(sum, ref.sum), 1e-6);
    worst.sum = std::max(worst.sum, rel_err(sum, ref.sum));
    worst.dl =
        std::max(worst.dl, std::abs(static_cast<long>(L) - static_cast<long>(ref.admissible)));

    // solve() without a filter is the plain average.
    PaperSpectrum plain = solver.solve(t, EdgeFilter());
    EXPECT_EQ(plain.admissible, L);
    EXPECT_EQ(plain.dropped, 0u);
    std::vector<double> ref_plain = ref.sum;
    for (double& v : ref_plain) v /= static_cast<double>(ref.admissible);
    EXPECT_LE(rel_err(plain.values, ref_plain), 1e-6);

    // Each partial solution reproduces the target, so the average does. 1e-5 relative: the
    // solver's triple kernels accumulate in float (paper_solver.cpp; the Spectralizer's exact
    // projection restores double precision), ~20k float terms per sample.
    Xyz got;
    for (std::size_t i = 0; i < n; ++i) got = got + plain.values[i] * w[i];
    EXPECT_LE(rel_err(got, t), 1e-5);
    worst.exact = std::max(worst.exact, rel_err(got, t));

    // Filtered: drop floor(0.7 L) of the largest; kept count and average must match.
    PaperSpectrum filt = solver.solve(t, EdgeFilter::fraction(0.7));
    EXPECT_EQ(filt.admissible, L);
    EXPECT_EQ(filt.admissible - filt.dropped, ref.kept)
        << "solver kept " << filt.admissible - filt.dropped << ", brute force kept " << ref.kept;
    EXPECT_LE(rel_err(filt.values, ref.average), 1e-6);
    worst.filtered = std::max(worst.filtered, rel_err(filt.values, ref.average));
    for (double v : filt.values) {
      EXPECT_GE(v, 0.0);  // an average of non-negative solutions
    }
  }
  std::printf("  worst vs brute force: |dL| %ld, sum %.2e, filtered %.2e, exactness %.2e\n",
              worst.dl, worst.sum, worst.filtered, worst.exact);
}

TEST(PaperSolver, MatchesBruteForceAt10nmEmission) {
  SampleWeights sw(WavelengthGrid::parse("380:780:10"), Observer::get("cie1931"), nullptr);
  compare_with_brute_force(sw.columns(), emission_colours(4, 7));
}

TEST(PaperSolver, MatchesBruteForceAt10nmReflectanceAndCie1964) {
  // Reflectance weights under D65 and A: targets W rho for random rho in [0, 1], which are
  // inside the cone by construction.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (const char* il_name : {"D65", "A"}) {
    SCOPED_TRACE(il_name);
    Illuminant il = Illuminant::get(il_name);
    SampleWeights sw(WavelengthGrid::parse("380:780:10"), Observer::get("cie1931"), &il);
    std::vector<Xyz> targets;
    for (int m = 0; m < 3; ++m) {
      std::vector<double> rho(sw.columns().size());
      for (double& v : rho) v = u(rng);
      targets.push_back(sw.integrate(rho));
    }
    compare_with_brute_force(sw.columns(), targets);
  }
  SampleWeights sw10(WavelengthGrid::parse("380:780:10"), Observer::get("cie1964"), nullptr);
  compare_with_brute_force(sw10.columns(), emission_colours(0, 0));
}

TEST(PaperSolver, MatchesBruteForceAt5nm) {
  SampleWeights sw(WavelengthGrid(), Observer::get("cie1931"), nullptr);
  std::vector<Xyz> colours = emission_colours(1, 3);
  colours.erase(colours.begin() + 2, colours.end() - 1);  // the light, the surface, one random
  ASSERT_EQ(colours.size(), 3u);
  compare_with_brute_force(sw.columns(), colours);
}

TEST(PaperSolver, CountFilterMatchesBruteForce) {
  // EdgeFilter::count(K) drops exactly K (when L > K): the brute force with K / L.
  SampleWeights sw(WavelengthGrid::parse("380:780:10"), Observer::get("cie1931"), nullptr);
  PaperSolver solver(sw.columns());
  const Xyz t = test::rgb(test::kRec709ToXyz, 0.21, 0.72, 0.15);
  std::vector<Partial> parts = brute_force_partials(sw.columns(), t);
  ASSERT_GT(parts.size(), 1000u);
  std::sort(parts.begin(), parts.end(),
            [](const Partial& x, const Partial& y) { return x.max_density < y.max_density; });
  const std::size_t kept = parts.size() - 1000;
  std::vector<double> ref = sum_of(parts, sw.columns().size(), kept);
  for (double& v : ref) v /= static_cast<double>(kept);
  PaperSpectrum got = solver.solve(t, EdgeFilter::count(1000));
  EXPECT_EQ(got.dropped, 1000u);
  EXPECT_LE(rel_err(got.values, ref), 1e-6);  // as above
  // Dropping more than L keeps the single smallest partial solution.
  PaperSpectrum one = solver.solve(t, EdgeFilter::count(100000000));
  EXPECT_EQ(one.admissible - one.dropped, 1u);
  EXPECT_LE(rel_err(one.values, sum_of(parts, sw.columns().size(), 1)), 1e-6);
}

TEST(PaperSolver, AutomaticFilterMatchesBruteForceLadder) {
  // EdgeFilter::automatic(): the first fraction of kAutoLadder whose average has no sample
  // within kEdgeBandNm of either grid end above the mean over 400-700 nm (the last step if
  // none). Reference: the brute force at each step, with that criterion written here.
  for (const char* gtext : {"380:780:10", "380:780:5"}) {
    SCOPED_TRACE(gtext);
    const WavelengthGrid grid = WavelengthGrid::parse(gtext);
    SampleWeights sw(grid, Observer::get("cie1931"), nullptr);
    std::vector<double> nm(grid.size());
    for (std::size_t i = 0; i < nm.size(); ++i) nm[i] = grid[i];
    PaperSolver solver(sw.columns(), nm);
    auto peak_free = [&](const std::vector<double>& v) {
      double mean = 0;
      int count = 0;
      for (std::size_t i = 0; i < v.size(); ++i)
        if (nm[i] >= 400 && nm[i] <= 700) mean += v[i], ++count;
      mean /= count;
      for (std::size_t i = 0; i < v.size(); ++i)
        if ((nm[i] <= nm.front() + EdgeFilter::kEdgeBandNm ||
             nm[i] >= nm.back() - EdgeFilter::kEdgeBandNm) &&
            v[i] > mean)
          return false;
      return true;
    };
    // Saturated colours need deep ladder steps; 10 nm: more colours, 5 nm: two.
    std::vector<Xyz> colours = {test::rgb(test::kRec709ToXyz, 0.882, 0.044, 0.136),
                                test::rgb(test::kRec709ToXyz, 0.1, 0.2, 0.9)};
    if (grid.size() < 60)
      for (const Xyz& c : emission_colours(4, 17)) colours.push_back(c);
    for (const Xyz& t : colours) {
      SCOPED_TRACE(::testing::Message() << "XYZ (" << t.X << ", " << t.Y << ", " << t.Z << ")");
      Brute ref;
      double chosen = 0;
      for (double f : EdgeFilter::kAutoLadder) {
        ref = brute_force(sw.columns(), t, f);
        chosen = f;
        if (peak_free(ref.average)) break;
      }
      PaperSpectrum got = solver.solve(t, EdgeFilter::automatic());
      EXPECT_EQ(got.admissible, ref.admissible);
      EXPECT_EQ(got.admissible - got.dropped, ref.kept) << "ladder step " << chosen;
      EXPECT_LE(rel_err(got.values, ref.average), 1e-6) << "ladder step " << chosen;  // as above
    }
  }
}

TEST(PaperSolver, ColoursOutsideTheLocusHaveNoAdmissibleSolution) {
  SampleWeights sw(WavelengthGrid::parse("380:780:10"), Observer::get("cie1931"), nullptr);
  PaperSolver solver(sw.columns());
  const std::vector<Xyz> outside = {
      {-0.1, 1.0, 0.1},                    // negative X: no non-negative spectrum makes it
      test::xyz_from_xy(0.3, 0.75, 1.0),   // above the spectral locus (y(550 nm) = 0.69)
      test::xyz_from_xy(0.05, 0.05, 0.2),  // left of the blue corner of the locus
      {0.5, -0.1, 0.5},                    // negative luminance
  };
  for (const Xyz& t : outside) {
    SCOPED_TRACE(::testing::Message() << "XYZ (" << t.X << ", " << t.Y << ", " << t.Z << ")");
    EXPECT_EQ(brute_force_partials(sw.columns(), t).size(), 0u);  // the oracle agrees
    std::vector<double> sum(sw.columns().size(), 1.0);
    EXPECT_EQ(solver.sum_admissible(t, sum), 0u);
    for (double v : sum) {
      EXPECT_EQ(v, 0.0);
    }
    for (const EdgeFilter& f : {EdgeFilter(), EdgeFilter::fraction(0.7)}) {
      PaperSpectrum p = solver.solve(t, f);
      EXPECT_EQ(p.admissible, 0u);
      for (double v : p.values) {
        EXPECT_EQ(v, 0.0);
      }
    }
  }
  // Zero has no chromaticity: nothing is admissible.
  EXPECT_EQ(solver.solve(Xyz{}, EdgeFilter()).admissible, 0u);
}

TEST(PaperSolver, IgnoresSamplesWithZeroWeight) {
  // On 360:830:0.5 every other sample has a zero weight vector (its tent misses all table
  // points); the solver must leave them at zero and still reproduce the colour exactly.
  SampleWeights sw(WavelengthGrid::parse("370:400:0.5"), Observer::get("cie1931"), nullptr);
  PaperSolver solver(sw.columns());
  // A target made by a positive spectrum on the non-zero samples: inside the cone.
  std::vector<double> phi(sw.columns().size(), 0.0);
  for (std::size_t i = 0; i < phi.size(); i += 2) phi[i] = 1.0 + 0.1 * static_cast<double>(i % 7);
  const Xyz t = sw.integrate(phi);
  PaperSpectrum p = solver.solve(t, EdgeFilter::fraction(0.7));
  ASSERT_GT(p.admissible, 0u);
  for (std::size_t i = 1; i < phi.size(); i += 2) {
    EXPECT_EQ(p.values[i], 0.0) << i;
  }
  Xyz got;
  for (std::size_t i = 0; i < phi.size(); ++i) got = got + p.values[i] * sw.columns()[i];
  EXPECT_LE(rel_err(got, t), 1e-5);  // exact partial solutions, averaged in float kernels
}

}  // namespace
}  // namespace spectralize
