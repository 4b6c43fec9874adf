// The exemplar model (--model exemplar, docs/DESIGN.md §6): its definition checked from its
// parts, independently of the model's code (the measured reflectances read from data/'s CSV
// files here, colours by this test's own reference integration, the projection checked by its
// optimality conditions), exactness and bounds near every exemplar, continuity across the edge
// of an exemplar's reach and across the natural fallback's threshold, natural lights, and what
// it does to greys. Exactness and bounds on random colours of three spaces are in
// bounded_models_test.cpp (parametrised over models).

#include "core/models/exemplar_model.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "core/colorimetry/colour_difference.h"
#include "core/solvers/natural_solver.h"
#include "spectralize/core/spectralizer.h"
#include "spectralizer_checks.h"
#include "test_support.h"

namespace spectralize {
namespace {

using namespace test;  // NOLINT: the checks of spectralizer_checks.h

constexpr double kH = 2.0;  // the model's stated constants (docs/MODEL_STUDY.md)
constexpr double kC = 0.1;

Spectralizer make_model(const std::string& model, Mode mode) {
  SpectralizerSettings s;
  s.mode = mode;
  s.model = model;
  return Spectralizer(s);
}

// The columns (reflectances) of a CSV file of data/, whose rows are 380..780 nm at 5 nm: the
// default grid, so no interpolation is needed.
std::vector<std::vector<double>> read_columns(const std::string& file) {
  std::ifstream in(std::string(SPECTRALIZE_DATA_DIR) + "/" + file);
  EXPECT_TRUE(in) << file;
  std::string line;
  std::getline(in, line);  // header
  std::vector<std::vector<double>> columns;
  int rows = 0;
  while (std::getline(in, line)) {
    std::stringstream cells(line);
    std::string cell;
    std::getline(cells, cell, ',');
    EXPECT_NEAR(std::stod(cell), 380 + 5 * rows, 1e-9) << file;
    for (std::size_t k = 0; std::getline(cells, cell, ','); ++k) {
      if (columns.size() <= k) columns.emplace_back();
      columns[k].push_back(std::stod(cell));
    }
    ++rows;
  }
  EXPECT_EQ(rows, 81) << file;
  return columns;
}

// One measured reflectance as the model must see it: its colour (this test's integration), its
// CIELAB relative to rho == 1 and the shape it blends in (clamped to [0, 1]).
struct Exemplar {
  std::vector<double> clamped;
  Xyz colour;
  Lab lab;
};

struct Library {
  Xyz white;
  std::vector<Exemplar> exemplars;
};

const Library& library() {
  static const Library lib = [] {
    const SpectralizerSettings defaults;
    const Observer& obs = Observer::get(defaults.observer);
    const Illuminant d65 = Illuminant::get("D65");
    Library l;
    l.white = reference_xyz(defaults.grid, std::vector<double>(81, 1.0), obs, &d65.spd);
    for (const char* file : {"colorchecker_n_ohta_5nm.csv", "ampas_rawtoaces_190_patches_5nm.csv"})
      for (std::vector<double>& rho : read_columns(file)) {
        Exemplar e;
        e.colour = reference_xyz(defaults.grid, rho, obs, &d65.spd);
        e.lab = to_lab(e.colour, l.white);
        for (double& v : rho) v = std::clamp(v, 0.0, 1.0);
        e.clamped = std::move(rho);
        l.exemplars.push_back(std::move(e));
      }
    return l;
  }();
  return lib;
}

// CIELAB back to XYZ (CIE 015's inverse), for targets at given CIELAB colours.
Xyz from_lab(const Lab& lab, const Xyz& white) {
  auto finv = [](double f) {
    constexpr double d = 6.0 / 29.0;
    return f > d ? f * f * f : 3 * d * d * (f - 4.0 / 29.0);
  };
  const double fy = (lab.L + 16) / 116;
  return {white.X * finv(fy + lab.a / 500), white.Y * finv(fy), white.Z * finv(fy - lab.b / 200)};
}

// The weights of the definition: w_j = (1 - (d_j / h)^2)^3 for d_j < h, d_j in CIEDE2000's
// metric at exemplar j.
std::vector<double> weights_of(const Xyz& target) {
  const Library& lib = library();
  const Lab t = to_lab(target, lib.white);
  std::vector<double> w;
  for (const Exemplar& e : lib.exemplars) {
    const double d2 =
        ciede2000_metric(e.lab).squared(t.L - e.lab.L, t.a - e.lab.a, t.b - e.lab.b) / (kH * kH);
    w.push_back(d2 < 1 ? std::pow(1 - d2, 3) : 0.0);
  }
  return w;
}

// The weight columns of the constraint by this test's own integration: W e_i.
const std::vector<Xyz>& columns() {
  static const std::vector<Xyz> c = [] {
    const SpectralizerSettings defaults;
    const Illuminant d65 = Illuminant::get("D65");
    std::vector<Xyz> out;
    for (std::size_t i = 0; i < 81; ++i) {
      std::vector<double> e(81, 0.0);
      e[i] = 1;
      out.push_back(reference_xyz(defaults.grid, e, Observer::get(defaults.observer), &d65.spd));
    }
    return out;
  }();
  return c;
}

// How far x is from being the least-squares projection of b onto {W x = t, 0 <= x <= 1}: its
// optimality conditions x = clamp(b + W^T nu) for some nu. nu by least squares on the free
// samples; the worst violation (0 at the projection).
double projection_violation(const std::vector<double>& x, const std::vector<double>& b) {
  const std::vector<Xyz>& c = columns();
  Mat3 a{};
  Xyz rhs;
  int free = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (x[i] <= 0 || x[i] >= 1) continue;
    ++free;
    for (int r = 0; r < 3; ++r) {
      for (int q = 0; q < 3; ++q) a[r][q] += c[i][r] * c[i][q];
      rhs[r] += c[i][r] * (x[i] - b[i]);
    }
  }
  if (free < 3) return INFINITY;
  const Xyz nu = mul(inverse(a), rhs);
  double worst = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double v = b[i] + dot(c[i], nu);  // before the clamp
    if (x[i] <= 0)
      worst = std::max(worst, v);  // clamped at 0: v <= 0
    else if (x[i] >= 1)
      worst = std::max(worst, 1 - v);  // clamped at 1: v >= 1
    else
      worst = std::max(worst, std::abs(x[i] - v));
  }
  return worst;
}

TEST(ExemplarModel, SpectraAreTheProjectedBlendOfTheDefinition) {
  // Around every one of the 214 measured colours, 4 targets at random CIELAB steps of up to
  // 4 units (the first at the colour itself): within h of some exemplar the spectrum is the
  // least-squares projection (optimality conditions to 1e-9) of (c x_natural + sum w_j rho_j) / (c
  // + sum w_j) with this test's weights, exact (1e-12, this test's integration) and bounded;
  // elsewhere it is the natural spectrum itself. The reported count of exemplars is this test's.
  const Spectralizer exemplar = make_model("exemplar", Mode::reflectance);
  const Spectralizer natural = make_model("natural", Mode::reflectance);
  const Reference ref = reference_of(exemplar);
  const Library& lib = library();
  ASSERT_EQ(lib.exemplars.size(), 214u);
  std::mt19937 rng(3);
  std::normal_distribution<double> g(0.0, 1.0);
  std::uniform_real_distribution<double> u(0.0, 4.0);
  int blended = 0, plain = 0;
  double worst_kkt = 0, worst_error = 0;
  for (const Exemplar& e : lib.exemplars)
    for (int k = 0; k < 4; ++k) {
      double d[3] = {g(rng), g(rng), g(rng)};
      const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
      const double s = k == 0 ? 0.0 : u(rng) / len;  // the first: the measured colour itself
      const Xyz t =
          from_lab({e.lab.L + s * d[0], e.lab.a + s * d[1], e.lab.b + s * d[2]}, lib.white);
      if (!exemplar.in_gamut(t) || !(t.Y > 0)) continue;
      const SpectrumResult r = exemplar.spectralize_target(t);
      ASSERT_EQ(r.status, Outcome::exact);
      const SpectrumResult n = natural.spectralize_target(t);
      for (double v : r.values) {
        ASSERT_GE(v, 0.0);
        ASSERT_LE(v, 1.0);
      }
      const double err = rel_err(integrate(exemplar, ref, r.values), t);
      worst_error = std::max(worst_error, err);
      EXPECT_LE(err, 1e-12);
      const std::vector<double> w = weights_of(t);
      double sum = 0;
      int count = 0;
      std::vector<double> blend = n.values;
      for (double& v : blend) v *= kC;
      for (std::size_t j = 0; j < w.size(); ++j) {
        if (w[j] == 0) continue;
        ++count;
        sum += w[j];
        for (std::size_t i = 0; i < blend.size(); ++i)
          blend[i] += w[j] * lib.exemplars[j].clamped[i];
      }
      EXPECT_EQ(r.detail("exemplars"), count);
      if (count == 0) {
        ++plain;
        EXPECT_EQ(r.values, n.values);
        EXPECT_EQ(r.detail("exemplar_weight"), 0.0);
        continue;
      }
      ++blended;
      for (double& v : blend) v /= kC + sum;
      EXPECT_NEAR(r.detail("exemplar_weight"), sum / (kC + sum), 1e-9);
      const double kkt = projection_violation(r.values, blend);
      worst_kkt = std::max(worst_kkt, kkt);
      EXPECT_LE(kkt, 1e-9);
    }
  std::printf("  %d blended (worst optimality violation %.1e), %d natural; worst error %.1e\n",
              blended, worst_kkt, plain, worst_error);
  EXPECT_GT(blended, 400);
  EXPECT_GT(plain, 100);
}

TEST(ExemplarModel, AtAMeasuredColourItIsCloseToTheMeasurement) {
  // At the colour of a measured material the blend is mostly its own shape (weight 1 against
  // c = 0.1): the spectrum is nearer the measurement than the natural one (RMS over the grid),
  // for nearly all of the 214, and much nearer on average.
  const Spectralizer exemplar = make_model("exemplar", Mode::reflectance);
  const Spectralizer natural = make_model("natural", Mode::reflectance);
  int nearer = 0, total = 0;
  double sum_e = 0, sum_n = 0;
  for (const Exemplar& e : library().exemplars) {
    const SpectrumResult r = exemplar.spectralize_target(e.colour);
    const SpectrumResult n = natural.spectralize_target(e.colour);
    if (r.status != Outcome::exact) continue;
    ++total;
    auto rms = [&](const std::vector<double>& x) {
      double s = 0;
      for (std::size_t i = 0; i < x.size(); ++i) s += std::pow(x[i] - e.clamped[i], 2);
      return std::sqrt(s / static_cast<double>(x.size()));
    };
    sum_e += rms(r.values);
    sum_n += rms(n.values);
    nearer += rms(r.values) < rms(n.values);
    EXPECT_GT(r.detail("exemplar_weight"), 1 / (1 + kC) - 1e-12);
  }
  std::printf("  nearer the measurement than natural: %d of %d (mean RMS %.4f against %.4f)\n",
              nearer, total, sum_e / total, sum_n / total);
  EXPECT_EQ(total, 214);
  EXPECT_GE(nearer, 200);
  EXPECT_LT(sum_e, 0.25 * sum_n);
}

// A model's detail `name` (0 when absent).
double detail(const ModelSolution& s, const std::string& name) {
  for (const ModelDetail& d : s.details)
    if (d.name == name) return d.value;
  return 0;
}

// The largest change between neighbouring spectra of a walk through `targets`, relative to the
// largest value, with exactness and bounds checked on the way.
double largest_step(const SpectrumModel& model, const std::vector<Xyz>& targets) {
  double worst = 0;
  std::vector<double> prev;
  for (const Xyz& t : targets) {
    const ModelSolution s = model.solve(t, 1.0);
    Xyz got;
    for (std::size_t i = 0; i < s.values.size(); ++i) got = got + s.values[i] * columns()[i];
    EXPECT_LE(rel_err(got, t), 1e-11);
    for (double v : s.values) {
      EXPECT_GE(v, 0.0);
      EXPECT_LE(v, 1.0);
    }
    if (!prev.empty()) {
      double jump = 0, top = 0;
      for (std::size_t i = 0; i < prev.size(); ++i) {
        jump = std::max(jump, std::abs(s.values[i] - prev[i]));
        top = std::max(top, prev[i]);
      }
      worst = std::max(worst, jump / top);
    }
    prev = s.values;
  }
  return worst;
}

ModelContext context_of(const Spectralizer& sp) {
  static std::vector<double> nm;
  nm.clear();
  for (std::size_t i = 0; i < sp.settings().grid.size(); ++i) nm.push_back(sp.settings().grid[i]);
  ModelContext c;
  c.columns = sp.weights().columns();
  c.wavelengths = nm;
  c.step_nm = sp.settings().grid.step();
  return c;
}

TEST(ExemplarModel, ContinuousAcrossTheEdgeOfAnExemplarsReach) {
  // From a measured colour outward in a CIELAB direction, through the edge of its reach (metric
  // distance h) to 1.5 h, walked in 30 and in 300 steps: a continuous path's largest step
  // shrinks ~10x with the step, a seam would keep its jump. Six exemplars (neutral, red,
  // magenta, blue, a skin tone, a dark AMPAS purple), three directions each. The walk starts at
  // full weight and ends out of the exemplar's reach (at the natural spectrum where no other
  // exemplar reaches).
  const Spectralizer sp = make_model("exemplar", Mode::reflectance);
  const ExemplarModel model(context_of(sp));
  const SpectralizerSettings natural_settings = [] {
    SpectralizerSettings s;
    s.mode = Mode::reflectance;
    s.model = "natural";
    return s;
  }();
  const Spectralizer natural(natural_settings);
  const Library& lib = library();
  for (std::size_t j : {21u, 14u, 16u, 12u, 1u, 24u + 156u}) {
    const Lab at = lib.exemplars[j].lab;
    const LabMetric q = ciede2000_metric(at);
    for (const auto& d :
         std::vector<std::array<double, 3>>{{1, 0, 0}, {0, 1, 0.3}, {0.2, -0.4, 1}}) {
      SCOPED_TRACE("exemplar " + std::to_string(j) + " direction " + std::to_string(d[0]) + "," +
                   std::to_string(d[1]) + "," + std::to_string(d[2]));
      const double unit = 1 / std::sqrt(q.squared(d[0], d[1], d[2]));  // CIELAB length of 1
      auto walk = [&](int steps) {
        std::vector<Xyz> targets;
        for (int k = 0; k <= steps; ++k) {
          const double s = 1.5 * kH * unit * k / steps;
          targets.push_back(
              from_lab({at.L + s * d[0], at.a + s * d[1], at.b + s * d[2]}, lib.white));
        }
        return targets;
      };
      const std::vector<Xyz> coarse = walk(30), fine = walk(300);
      const ModelSolution first = model.solve(fine.front(), 1.0);
      const ModelSolution last = model.solve(fine.back(), 1.0);
      EXPECT_GT(detail(first, "exemplar_weight"), 1 / (1 + kC) - 1e-12);
      const std::vector<double> w = weights_of(fine.back());
      EXPECT_EQ(w[j], 0.0);
      if (std::all_of(w.begin(), w.end(), [](double v) { return v == 0; })) {
        EXPECT_EQ(last.values, natural.spectralize_target(fine.back()).values);
      }
      const double big = largest_step(model, coarse), small = largest_step(model, fine);
      EXPECT_LE(small, 0.25 * big) << "coarse " << big << " fine " << small;
    }
  }
}

TEST(ExemplarModel, FallbackIsContinuousAcrossItsThreshold) {
  // The natural model's fallback test, for the exemplar model: a gradient that crosses the
  // natural zone's edge (depth 0.999) toward the gamut boundary in 30 and in 300 steps, six
  // Rec.2020 hues at two luminances; the largest step shrinks with the step (4x required).
  const Spectralizer sp = make_model("exemplar", Mode::reflectance);
  const ExemplarModel model(context_of(sp));
  const NaturalSolver solver(sp.weights().columns(), 5.0);
  const Xyz white = sp.reference_white();
  for (double level : {0.15, 0.4})
    for (const auto& c : std::vector<std::array<double, 3>>{{1, 0.1, 0.05},
                                                            {0.1, 1, 0.1},
                                                            {0.1, 0.2, 1},
                                                            {1, 1, 0.05},
                                                            {0.05, 1, 1},
                                                            {1, 0.1, 1}}) {
      const Xyz colour = sp.target_of(level * rgb(kRec2020ToXyz, c[0], c[1], c[2]));
      const Xyz grey = (colour.Y / white.Y) * white;
      const double depth = solver.depth(colour, 1.0);
      ASSERT_TRUE(std::isfinite(depth) && depth > 0);
      auto walk = [&](int steps) {
        std::vector<Xyz> targets;
        for (int k = 0; k <= steps; ++k) {
          const double d = 0.998 + 0.0015 * k / steps;
          targets.push_back(grey + (d / depth) * (colour - grey));
        }
        return targets;
      };
      const double big = largest_step(model, walk(30)), small = largest_step(model, walk(300));
      EXPECT_LE(small, 0.25 * big) << "coarse " << big << " fine " << small;
      EXPECT_GT(detail(model.solve(walk(1).back(), 1.0), "fallback_weight"), 0.0);
    }
}

TEST(ExemplarModel, LightsAreTheNaturalModels) {
  // Emission has no exemplars: the spectrum of every light is the natural model's, bit for bit.
  const Spectralizer exemplar = make_model("exemplar", Mode::emission);
  const Spectralizer natural = make_model("natural", Mode::emission);
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> u(0.0, 2.0);
  for (int i = 0; i < 300; ++i) {
    const Xyz xyz = rgb(kRec709ToXyz, u(rng), u(rng), u(rng));
    EXPECT_EQ(exemplar.spectralize(xyz).values, natural.spectralize(xyz).values) << i;
  }
}

TEST(ExemplarModel, GreysNearAMeasuredNeutralTakeItsShape) {
  // Measured greys are not flat: paint absorbs in the violet (the ColorChecker's neutral 5
  // reflects 0.11 at 380 nm and 0.20 at 550 nm). A grey at that patch's colour takes its shape
  // (the violet end below the middle, as measured), and a grey out of every exemplar's reach
  // is flat (the natural model's: 1e-6).
  const Spectralizer sp = make_model("exemplar", Mode::reflectance);
  const Library& lib = library();
  const Exemplar& neutral5 = lib.exemplars[21];
  ASSERT_LT(neutral5.clamped[0], 0.6 * neutral5.clamped[34]);  // 380 nm against 550 nm
  const Xyz grey = (neutral5.colour.Y / lib.white.Y) * lib.white;
  const SpectrumResult at = sp.spectralize_target(grey);
  EXPECT_GT(at.detail("exemplars"), 0);
  EXPECT_LT(at.values[0], 0.8 * at.values[34]);
  // A grey level no exemplar reaches.
  int flat = 0;
  for (double level = 0.02; level < 0.95; level += 0.01) {
    const Xyz t = level * lib.white;
    const std::vector<double> w = weights_of(t);
    if (std::any_of(w.begin(), w.end(), [](double v) { return v > 0; })) continue;
    const SpectrumResult r = sp.spectralize_target(t);
    for (double v : r.values) {
      EXPECT_NEAR(v, level, 1e-6 * level);
    }
    ++flat;
  }
  EXPECT_GT(flat, 10);
}

}  // namespace
}  // namespace spectralize
