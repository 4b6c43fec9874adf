// The Jakob & Hanika baseline (src/baseline/sigmoid_spectrum.h): the formula, the fit's accuracy,
// the table's layout and interpolation. Every colour is checked by the test's own oracle: the
// sigmoid written out here, sampled on the grid and integrated by test_support's trapezoid rule
// over the CSV tables (docs/DESIGN.md §3), white-balanced by XYZ scaling, in CIELAB.

#include "baseline/sigmoid_spectrum.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "core/colorimetry/colour_difference.h"
#include "test_support.h"

namespace spectralize::baseline {
namespace {

using test::kRec2020ToXyz;
using test::kRec709ToXyz;

// The formula, written out: s = 1/2 + x / (2 sqrt(1 + x^2)), x = c0 nm^2 + c1 nm + c2.
double oracle_value(double c0, double c1, double c2, double nm) {
  const double x = c0 * nm * nm + c1 * nm + c2;
  return 0.5 + x / (2 * std::sqrt(1 + x * x));
}

double srgb_decode(double v) {
  return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
}

// The colour measurement of one space on one grid under D65, from the test's own integration.
struct Oracle {
  WavelengthGrid grid;
  const Observer& obs = Observer::get("cie1931");
  std::vector<double> d65 = Illuminant::get("D65").spd;
  test::Mat3 m;
  Xyz white;  // XYZ of rho == 1

  Oracle(const test::Mat3& rgb_to_xyz, WavelengthGrid g = {}) : grid(g), m(rgb_to_xyz) {
    white = test::reference_xyz(grid, std::vector<double>(grid.size(), 1.0), obs, &d65);
  }
  // XYZ scaling of the D65 white to the reference white (docs/DESIGN.md §3).
  Xyz target(const std::array<double, 3>& rgb) const {
    const Xyz xyz = test::rgb(m, rgb[0], rgb[1], rgb[2]), w = test::d65_white();
    return {xyz.X * white.X / w.X, xyz.Y * white.Y / w.Y, xyz.Z * white.Z / w.Z};
  }
  std::vector<double> samples(double c0, double c1, double c2) const {
    std::vector<double> s(grid.size());
    for (std::size_t i = 0; i < s.size(); ++i) s[i] = oracle_value(c0, c1, c2, grid[i]);
    return s;
  }
  // Delta E 1976 between the target of rgb and the sampled sigmoid of (c0, c1, c2).
  double delta_e(const std::array<double, 3>& rgb, double c0, double c1, double c2) const {
    const Lab want = to_lab(target(rgb), white);
    const Lab got = to_lab(test::reference_xyz(grid, samples(c0, c1, c2), obs, &d65), white);
    return std::sqrt((got.L - want.L) * (got.L - want.L) + (got.a - want.a) * (got.a - want.a) +
                     (got.b - want.b) * (got.b - want.b));
  }
};

// Colours uniform in the encoded sRGB cube, decoded to linear (like texture values).
std::vector<std::array<double, 3>> random_colours(std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<std::array<double, 3>> c(n);
  for (auto& rgb : c)
    for (double& v : rgb) v = srgb_decode(u(rng));
  return c;
}

TEST(SigmoidPolynomial, EvaluatesTheFormulaInFloatAndDouble) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> a(-3e-4, 3e-4), b(-0.3, 0.3), nm(360, 830);
  for (int n = 0; n < 1000; ++n) {
    const double c0 = a(rng), c1 = b(rng);
    const double c2 = -(c0 * 550 * 550 + c1 * 550) + 5 * b(rng);  // x of order 1 near 550 nm
    const BasicSigmoidPolynomial<double> pd{c0, c1, c2};
    const double l = nm(rng);
    EXPECT_NEAR(pd(l), oracle_value(c0, c1, c2, l), 1e-12);
    // Float (what renderers store): the same coefficients rounded, the value to float accuracy.
    const SigmoidPolynomial pf{float(c0), float(c1), float(c2)};
    EXPECT_NEAR(pf(float(l)), oracle_value(pf.c0, pf.c1, pf.c2, float(l)), 2e-4);
    const float ls[4] = {float(l), 400.f, 555.5f, 700.f};
    float out[4];
    pf.eval4(ls, out);
    for (int i = 0; i < 4; ++i) {
      EXPECT_EQ(out[i], pf(ls[i]));
    }
  }
  // The constant spectra 1 and 0 (pbrt's grey special case at rgb 1 and 0).
  const float inf = INFINITY;
  EXPECT_EQ((SigmoidPolynomial{0, 0, inf})(500.f), 1.0f);
  EXPECT_EQ((SigmoidPolynomial{0, 0, -inf})(500.f), 0.0f);
  EXPECT_EQ((SigmoidPolynomial{0, 0, 0})(500.f), 0.5f);
}

TEST(SigmoidPolynomial, NormalisedCoefficientsConvertToNm) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-50, 50), nm(360, 830);
  for (int n = 0; n < 200; ++n) {
    const std::array<double, 3> c = {u(rng), u(rng), u(rng)};
    const auto p = to_nm(c);
    const double l = nm(rng), t = (l - 360) / 470;
    EXPECT_NEAR(p.c0 * l * l + p.c1 * l + p.c2, (c[0] * t + c[1]) * t + c[2], 1e-9);
  }
}

// The sigmoid reaches all of sRGB: the direct fit of 3000 random sRGB colours stops at its
// tolerance (measured max Delta E 76 1.0e-6; bound 1e-4). The fit's reported Delta E is the
// oracle's.
TEST(SigmoidFit, ReachesSmallDeltaEOnRandomSrgbColours) {
  const Oracle oracle(kRec709ToXyz);
  const SigmoidFitter fitter(kRec709ToXyz);
  double worst = 0, sum = 0;
  const auto colours = random_colours(3000, 11);
  for (const auto& rgb : colours) {
    const SigmoidFit f = fitter.fit(rgb);
    const auto& p = f.polynomial;
    const double de = oracle.delta_e(rgb, p.c0, p.c1, p.c2);
    EXPECT_NEAR(f.delta_e76, de, 1e-6 + 1e-6 * de);
    worst = std::max(worst, de);
    sum += de;
    for (double s : oracle.samples(p.c0, p.c1, p.c2)) {
      EXPECT_GT(s, 0.0);
      EXPECT_LT(s, 1.0);
    }
  }
  RecordProperty("max_delta_e76", std::to_string(worst));
  std::printf("direct fit, %zu random sRGB colours: max dE76 %.2e, mean %.2e\n", colours.size(),
              worst, sum / colours.size());
  EXPECT_LT(worst, 1e-4);
}

// Grey is a flat spectrum: c0 = c1 = 0, and the fit is found from any start.
TEST(SigmoidFit, GreyIsFlatAndTheFitIsFoundFromAnyStart) {
  const SigmoidFitter fitter(kRec709ToXyz);
  const Oracle oracle(kRec709ToXyz);
  const SigmoidFit grey = fitter.fit({0.3, 0.3, 0.3});
  EXPECT_LT(grey.delta_e76, 1e-6);
  for (double nm : {380.0, 550.0, 780.0}) {
    EXPECT_NEAR(grey.polynomial(nm), 0.3, 1e-6);
  }
  for (const auto& start : {std::array<double, 3>{5, -5, 1}, std::array<double, 3>{-20, 20, -3}}) {
    const SigmoidFit a = fitter.fit({0.6, 0.2, 0.1}), b = fitter.fit({0.6, 0.2, 0.1}, start);
    for (double nm : {400.0, 500.0, 600.0, 700.0}) {
      EXPECT_NEAR(a.polynomial(nm), b.polynomial(nm), 1e-4);
    }
  }
}

// Any space by its matrix, on any grid: sRGB colours given in Rec.2020 coordinates are the same
// colours, reached as well (measured max Delta E 76 1e-6 on a 10 nm grid; bound 1e-4).
TEST(SigmoidFit, OtherSpacesAndGrids) {
  const WavelengthGrid coarse(380, 780, 10);
  const test::Mat3 to2020 = test::matmul(test::inverse(kRec2020ToXyz), kRec709ToXyz);
  const Oracle oracle(kRec2020ToXyz, coarse);
  const SigmoidFitter fitter(kRec2020ToXyz, {.grid = coarse});
  double worst = 0;
  for (const auto& c : random_colours(500, 5)) {
    const Xyz v = test::mul(to2020, {c[0], c[1], c[2]});
    const std::array<double, 3> rgb = {v.X, v.Y, v.Z};
    const auto p = fitter.fit(rgb).polynomial;
    worst = std::max(worst, oracle.delta_e(rgb, p.c0, p.c1, p.c2));
  }
  std::printf("direct fit, 500 sRGB colours as Rec.2020 RGB (10 nm grid): max dE76 %.2e\n", worst);
  EXPECT_LT(worst, 1e-4);
  test::expect_error_mentioning(
      [] {
        SigmoidFitterSettings bad;
        bad.illuminant = "D99x";
        SigmoidFitter(kRec709ToXyz, bad);
      },
      {"D99x"}, "unknown illuminant");
  test::expect_error_mentioning(
      [] {
        SigmoidFitterSettings bad;
        bad.max_coefficient = 0;
        SigmoidFitter(kRec709ToXyz, bad);
      },
      {"max_coefficient"}, "no room for coefficients");
  test::expect_error_mentioning([] { SigmoidTable(SigmoidFitter(kRec709ToXyz), 1); },
                                {"resolution"}, "resolution 1");
}

double smoothstep(double x) {
  return x * x * (3 - 2 * x);
}

// Each test is its own process under CTest: the tables are built on first use, at 16^3 (12k
// fits, ~0.1 s).
class SigmoidTableTest : public ::testing::Test {
 protected:
  static constexpr int kRes = 16;
  // rgb2spec's bound (the default) and none.
  static const SigmoidTable& table() {
    static const SigmoidFitter fitter(kRec709ToXyz);
    static const SigmoidTable t(fitter, kRes, 2);
    return t;
  }
  static const SigmoidTable& unbounded() {
    static const SigmoidFitter fitter(kRec709ToXyz, [] {
      SigmoidFitterSettings unbounded;
      unbounded.max_coefficient = INFINITY;
      return unbounded;
    }());
    static const SigmoidTable t(fitter, kRes, 2);
    return t;
  }
  // The largest oracle Delta E 76 of nodes (every k, every third j and i) whose largest
  // component is at least `min_z`.
  static double worst_node(const SigmoidTable& table, double min_z) {
    const Oracle oracle(kRec709ToXyz);
    double worst = 0;
    for (int m = 0; m < 3; ++m)
      for (int k = 0; k < kRes; ++k)
        for (int j = 0; j < kRes; j += 3)
          for (int i = 0; i < kRes; i += 3) {
            const auto rgb = node_rgb(m, k, j, i);
            if (rgb[m] < min_z) continue;
            const SigmoidPolynomial p = table.node(m, k, j, i);
            worst = std::max(worst, oracle.delta_e({rgb[0], rgb[1], rgb[2]}, p.c0, p.c1, p.c2));
          }
    return worst;
  }
  // The colour of node (m, k, j, i) by the layout's definition.
  static std::array<float, 3> node_rgb(int m, int k, int j, int i) {
    const float z = float(smoothstep(smoothstep(k / double(kRes - 1))));
    std::array<float, 3> rgb;
    rgb[m] = z;
    rgb[(m + 1) % 3] = z * float(i / double(kRes - 1));
    rgb[(m + 2) % 3] = z * float(j / double(kRes - 1));
    return rgb;
  }
};

void expect_same(const SigmoidPolynomial& a, const SigmoidPolynomial& b, double tol,
                 const std::string& what) {
  const double scale = std::max({std::abs(b.c0) * 600.0 * 600.0, std::abs(b.c1) * 600.0,
                                 double(std::abs(b.c2)), 1.0});  // the terms at 600 nm
  EXPECT_NEAR(a.c0 * 600 * 600, b.c0 * 600 * 600, tol * scale) << what;
  EXPECT_NEAR(a.c1 * 600, b.c1 * 600, tol * scale) << what;
  EXPECT_NEAR(a.c2, b.c2, tol * scale) << what;
}

TEST_F(SigmoidTableTest, ZAxisIsSmoothstepOfSmoothstep) {
  ASSERT_EQ(table().resolution(), kRes);
  for (int k = 0; k < kRes; ++k) {
    EXPECT_FLOAT_EQ(table().z_node(k), float(smoothstep(smoothstep(k / double(kRes - 1)))));
  }
}

// At a node the fetch is the node (x, y strictly below 1, so the largest component is unique).
TEST_F(SigmoidTableTest, FetchAtANodeReturnsTheNode) {
  for (int m = 0; m < 3; ++m)
    for (int k = 1; k < kRes; k += 3)
      for (int j = 0; j < kRes - 1; j += 2)
        for (int i = 0; i < kRes - 1; i += 3) {
          const auto rgb = node_rgb(m, k, j, i);
          expect_same(table()(rgb[0], rgb[1], rgb[2]), table().node(m, k, j, i), 1e-5,
                      "node " + std::to_string(m) + "," + std::to_string(k) + "," +
                          std::to_string(j) + "," + std::to_string(i));
        }
}

// Between nodes the fetch is the trilinear blend of the cell's 8 nodes, in (x, y) the ratios
// and in z the position between the two z nodes.
TEST_F(SigmoidTableTest, FetchBetweenNodesIsTrilinear) {
  std::mt19937 rng(9);
  std::uniform_int_distribution<int> cell(0, kRes - 2), block(0, 2);
  std::uniform_real_distribution<double> f(0.05, 0.95);
  for (int n = 0; n < 500; ++n) {
    const int m = block(rng), i = cell(rng), j = cell(rng), k = 1 + cell(rng) % (kRes - 2);
    const double fx = f(rng), fy = f(rng), fz = f(rng);
    const double z0 = smoothstep(smoothstep(k / double(kRes - 1)));
    const double z1 = smoothstep(smoothstep((k + 1) / double(kRes - 1)));
    const double z = z0 + fz * (z1 - z0);
    std::array<float, 3> rgb;
    rgb[m] = float(z);
    rgb[(m + 1) % 3] = float(z * (i + fx) / (kRes - 1));
    rgb[(m + 2) % 3] = float(z * (j + fy) / (kRes - 1));
    std::array<double, 3> want{};
    for (int dz = 0; dz < 2; ++dz)
      for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 2; ++dx) {
          const SigmoidPolynomial c = table().node(m, k + dz, j + dy, i + dx);
          const double w = (dx ? fx : 1 - fx) * (dy ? fy : 1 - fy) * (dz ? fz : 1 - fz);
          want[0] += w * c.c0, want[1] += w * c.c1, want[2] += w * c.c2;
        }
    expect_same(table()(rgb[0], rgb[1], rgb[2]),
                SigmoidPolynomial{float(want[0]), float(want[1]), float(want[2])}, 1e-4,
                "cell " + std::to_string(n));
  }
}

// Equal components: the exact constant spectrum (0 and 1 included).
TEST_F(SigmoidTableTest, GreysAreConstant) {
  for (float g : {0.0f, 0.01f, 0.18f, 0.5f, 0.9f, 1.0f}) {
    const SigmoidPolynomial p = table()(g, g, g);
    for (float nm : {380.f, 555.f, 780.f}) {
      EXPECT_NEAR(p(nm), g, 1e-6) << g;
    }
  }
}

// Through a 16^3 table: measured max Delta E 76 8.0 over 3000 random sRGB colours (24^3: 5.4,
// 64^3: 1.33, tests/bench/sigmoid_study.cpp); bound 9. Spectra stay within (0, 1).
TEST_F(SigmoidTableTest, TableReachesSmallDeltaEOnRandomSrgbColours) {
  const Oracle oracle(kRec709ToXyz);
  double worst = 0;
  const auto colours = random_colours(3000, 13);
  for (const auto& rgb : colours) {
    const SigmoidPolynomial p = table()(float(rgb[0]), float(rgb[1]), float(rgb[2]));
    const std::array<double, 3> rgbf = {float(rgb[0]), float(rgb[1]), float(rgb[2])};
    worst = std::max(worst, oracle.delta_e(rgbf, p.c0, p.c1, p.c2));
    for (float nm = 360; nm <= 830; nm += 7.5f) {
      EXPECT_GT(p(nm), 0.0f);
      EXPECT_LT(p(nm), 1.0f);
    }
  }
  std::printf("%d^3 table, %zu random sRGB colours: max dE76 %.4f\n", kRes, colours.size(), worst);
  EXPECT_LT(worst, 9.0);
}

// Each node is its colour's fit. rgb2spec's bound (200) limits the darkest saturated nodes
// (here z <= 0.03: up to 9.9; in the 64^3 table z < 0.03: up to 1.1) and, slightly, the
// brightest near-white ones: measured max Delta E 76 0.072 for z >= 0.05; bound 0.1. Without
// the bound every node but black (z = 0, which no finite coefficients reach) is its colour to
// the float rounding of its coefficients: measured 9e-4; bound 2e-3.
TEST_F(SigmoidTableTest, NodesAreTheirColoursFits) {
  const double bounded = worst_node(table(), 0.05), free = worst_node(unbounded(), 1e-9);
  std::printf("%d^3 nodes: bounded (z >= 0.05) max dE76 %.2e, unbounded (z > 0) %.2e\n", kRes,
              bounded, free);
  EXPECT_LT(bounded, 0.1);
  EXPECT_LT(free, 2e-3);
  EXPECT_LT(table().max_node_delta_e(), 12.0);
  EXPECT_LT(unbounded().max_node_delta_e(), 0.01);
}

}  // namespace
}  // namespace spectralize::baseline
