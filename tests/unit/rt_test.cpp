// The render-time evaluator (include/spectralize/rt.h) on tables made by `spectralize table`
// (the CTest fixture rt_tables), through the C API: every colour of the gamut gets an exact
// bounded spectrum (the test's own integration of the CSV tables, never the library's weights;
// the colour spaces' standard matrices; its own gamut from its own weights), cells on the
// gamut's boundary included; colours outside are mapped as the core maps them; node spectra
// are the model's; bad files are refused with a message. Meta-tests show that a perturbed node
// or a table of other settings fails these checks.

#include <gtest/gtest.h>

// rt's definitions (include/spectralize/rt_impl.hpp) for rt_tests, rt_hostile_test.cpp's too.
#define SPECTRALIZE_RT_IMPLEMENTATION
#include <spectralize/rt.h>
#include <spectralize/rt_format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "spectralize/core/spectralizer.h"
#include "test_support.h"

namespace spectralize {
namespace {

namespace fs = std::filesystem;
using test::Mat3;

std::string table_path(const std::string& name) {
  return std::string(SPECTRALIZE_RT_TABLES) + "/" + name + ".spztab";
}

struct TableCase {
  std::string name;  // file stem: <space>_<mode>
  Mat3 rgb_to_xyz;   // the space's standard matrix (test_support.h), not the table's
  bool reflectance;
};

void PrintTo(const TableCase& c, std::ostream* os) {
  *os << c.name;
}

std::vector<TableCase> cases() {
  return {{"srgb_reflectance", test::kRec709ToXyz, true},
          {"rec2020_reflectance", test::kRec2020ToXyz, true},
          {"acescg_reflectance", test::acescg_to_xyz_d65(), true},
          {"aces2065_reflectance", test::aces2065_to_xyz_d65(), true},
          {"srgb_emission", test::kRec709ToXyz, false},
          {"rec2020_emission", test::kRec2020ToXyz, false},
          {"acescg_emission", test::acescg_to_xyz_d65(), false},
          {"aces2065_emission", test::aces2065_to_xyz_d65(), false}};
}

// The conventions of docs/DESIGN.md §3 from the test's own integration: the weight of each
// sample (reference_xyz of the unit spectrum at that sample) and the white balance.
struct Conventions {
  bool reflectance = true;
  Mat3 m{};              // RGB -> XYZ (D65)
  std::vector<Xyz> w;    // per-sample weights
  Xyz balance{1, 1, 1};  // target = XYZ (.) balance
  Xyz white;             // reflectance: the XYZ of rho == 1

  Conventions(bool refl, const Mat3& matrix, const std::string& illuminant = "D65")
      : reflectance(refl), m(matrix) {
    const WavelengthGrid grid;
    const Observer& obs = Observer::get("cie1931");
    const Illuminant il = Illuminant::get(illuminant);
    for (std::size_t k = 0; k < grid.size(); ++k) {
      std::vector<double> e(grid.size(), 0.0);
      e[k] = 1;
      w.push_back(test::reference_xyz(grid, e, obs, refl ? &il.spd : nullptr));
      white = white + w.back();
    }
    const Xyz d65 = test::d65_white();
    if (refl) balance = {white.X / d65.X, white.Y / d65.Y, white.Z / d65.Z};
  }
  Xyz target(const float rgb[3]) const {
    const Xyz x = test::rgb(m, rgb[0], rgb[1], rgb[2]);
    return {x.X * balance.X, x.Y * balance.Y, x.Z * balance.Z};
  }
  Xyz xyz_of(const std::vector<float>& s) const {
    Xyz c;
    for (std::size_t k = 0; k < w.size(); ++k) c = c + static_cast<double>(s[k]) * w[k];
    return c;
  }
  // The RGB of a target (inverse of target()).
  std::array<float, 3> rgb_of(const Xyz& t) const {
    const Xyz x{t.X / balance.X, t.Y / balance.Y, t.Z / balance.Z};
    const Xyz c = test::mul(test::inverse(m), x);
    return {static_cast<float>(c.X), static_cast<float>(c.Y), static_cast<float>(c.Z)};
  }
};

// The gamut from the test's own weights: the zonotope {W rho : 0 <= rho <= 1} (every facet is
// spanned by two generators), or for lights the convex hull of the weights' chromaticities
// (the spectral locus of the grid: any phi >= 0 has a chromaticity inside it).
struct TestGamut {
  bool zonotope = true;
  std::vector<std::array<double, 4>> planes;      // unit normal, offset (hull: in xy)
  std::vector<std::array<std::size_t, 2>> pairs;  // the generators spanning each facet / edge
  double scale = 1;

  TestGamut(const std::vector<Xyz>& w, bool zono) : zonotope(zono) {
    Xyz sum;
    for (const Xyz& c : w) sum = sum + c;
    scale = sum.max_abs();
    if (zonotope) {
      for (std::size_t i = 0; i < w.size(); ++i)
        for (std::size_t j = i + 1; j < w.size(); ++j) {
          Xyz n = cross(w[i], w[j]);
          const double len = std::sqrt(dot(n, n));
          if (!(len > 1e-12 * std::sqrt(dot(w[i], w[i]) * dot(w[j], w[j])))) continue;
          n = (1 / len) * n;
          double pos = 0, neg = 0;
          for (const Xyz& c : w) (dot(n, c) > 0 ? pos : neg) += dot(n, c);
          planes.push_back({n.X, n.Y, n.Z, pos}), pairs.push_back({i, j});
          planes.push_back({-n.X, -n.Y, -n.Z, -neg}), pairs.push_back({i, j});
        }
      return;
    }
    // Gift wrapping of the chromaticities, counter-clockwise from the lowest-x point.
    std::vector<std::array<double, 2>> c;
    for (const Xyz& g : w) c.push_back({g.X / g.sum(), g.Y / g.sum()});
    std::size_t start = 0;
    for (std::size_t k = 1; k < c.size(); ++k)
      if (c[k][0] < c[start][0]) start = k;
    std::size_t at = start;
    do {
      std::size_t next = (at + 1) % c.size();
      for (std::size_t k = 0; k < c.size(); ++k) {
        const double turn = (c[next][0] - c[at][0]) * (c[k][1] - c[at][1]) -
                            (c[next][1] - c[at][1]) * (c[k][0] - c[at][0]);
        const double far = std::hypot(c[k][0] - c[at][0], c[k][1] - c[at][1]) >
                           std::hypot(c[next][0] - c[at][0], c[next][1] - c[at][1]);
        if (turn < 0 || (turn == 0 && far)) next = k;
      }
      double nx = c[next][1] - c[at][1], ny = c[at][0] - c[next][0];
      const double len = std::hypot(nx, ny);
      nx /= len, ny /= len;
      planes.push_back({nx, ny, 0, nx * c[at][0] + ny * c[at][1]}), pairs.push_back({at, next});
      at = next;
    } while (at != start && planes.size() <= c.size());
  }
  // Reflectance: max over facets of n . t - d relative to the solid's size. Light: the signed
  // distance of t's chromaticity to the hull in xy (outside when X+Y+Z <= 0).
  double distance(const Xyz& t) const {
    double best = -INFINITY;
    if (zonotope) {
      for (const auto& p : planes)
        best = std::max(best, p[0] * t.X + p[1] * t.Y + p[2] * t.Z - p[3]);
      return best / scale;
    }
    if (!(t.sum() > 0)) return 1;
    const double x = t.X / t.sum(), y = t.Y / t.sum();
    for (const auto& p : planes) best = std::max(best, p[0] * x + p[1] * y - p[3]);
    return best;
  }
};

spz_table* load(const std::string& name) {
  char error[512];
  spz_table* t = spz_table_load(table_path(name).c_str(), error, sizeof error);
  EXPECT_NE(t, nullptr) << error;
  return t;
}

std::vector<float> samples(const spz_spectrum& s) {
  std::vector<float> v(81);
  spz_samples(&s, v.data());
  return v;
}

// Colours of a case: uniform in the cube, uniform in the gamut's bounding box (its RGB), on
// the gamut's boundary and just inside it, and the cube's corners.
std::vector<std::array<float, 3>> colours_of(const TableCase& tc, const Conventions& cv,
                                             const TestGamut& gamut, std::size_t n) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u01(0, 1);
  std::vector<std::array<float, 3>> out;
  for (int c = 0; c < 8; ++c) out.push_back({float(c & 1), float((c >> 1) & 1), float(c >> 2)});
  // The bounding box of the gamut in RGB (reflectance), or a wide box of lights.
  Xyz lo{-0.6, -0.6, -0.6}, hi{1.6, 1.6, 1.6};
  if (tc.reflectance) {
    lo = hi = Xyz{};
    const Mat3 inv = test::inverse(cv.m);
    for (const Xyz& g : cv.w) {
      const Xyz h = test::mul(inv, Xyz{g.X / cv.balance.X, g.Y / cv.balance.Y, g.Z / cv.balance.Z});
      for (int a = 0; a < 3; ++a) lo[a] += std::min(h[a], 0.0), hi[a] += std::max(h[a], 0.0);
    }
  }
  const std::size_t quarter = n / 4;
  for (std::size_t k = 0; k < quarter; ++k)
    out.push_back({float(u01(rng)), float(u01(rng)), float(u01(rng))});
  for (std::size_t k = 0; k < quarter; ++k) {
    std::array<float, 3> c;
    for (int a = 0; a < 3; ++a) c[a] = float(lo[a] + (hi[a] - lo[a]) * u01(rng));
    out.push_back(c);
  }
  // On a facet: the generators on its positive side at 1, the two spanning it in between; just
  // inside: 1e-6 of the way toward the grey (white light) of its luminance.
  std::uniform_int_distribution<std::size_t> pick(0, gamut.planes.size() - 1);
  while (out.size() < n) {
    const std::size_t f = pick(rng);
    const auto& p = gamut.planes[f];
    const Xyz nrm{p[0], p[1], p[2]};  // reflectance: the facet's normal
    Xyz t;
    const auto [i, j] = gamut.pairs[f];
    if (tc.reflectance) {
      for (std::size_t k = 0; k < cv.w.size(); ++k)
        if (k != i && k != j && dot(nrm, cv.w[k]) > 0) t = t + cv.w[k];
      t = t + u01(rng) * cv.w[i] + u01(rng) * cv.w[j];
    } else {  // on an edge of the locus: two samples' light
      t = (0.1 + u01(rng)) * (1 / cv.w[i].sum()) * cv.w[i] +
          (0.1 + u01(rng)) * (1 / cv.w[j].sum()) * cv.w[j];
      t = (1 / t.Y) * t;
    }
    if (!(t.Y > 0)) continue;
    const Xyz grey =
        tc.reflectance ? t.Y * cv.white : (t.Y / test::d65_white().Y) * test::d65_white();
    out.push_back(cv.rgb_of(t));
    out.push_back(cv.rgb_of(grey + (1 - 1e-6) * (t - grey)));
  }
  if (!tc.reflectance)  // lights of any brightness
    for (auto& c : out) {
      const float k = float(std::pow(10.0, 4 * u01(rng) - 2));
      for (float& v : c) v *= k;
    }
  return out;
}

// The test's gamut (its own integration) and the library's agree to ~1e-9 of the gamut's size:
// colours closer to the boundary than this may fall either side (and are then exact, or
// mapped as the CLI maps them).
constexpr double kBand = 1e-8;

struct Tally {
  std::size_t colours = 0, feasible = 0, exact = 0, mapped = 0, negative = 0, ambiguous = 0;
  std::size_t inexact = 0, out_of_bounds = 0, wrong_status = 0, snapped = 0;
  double worst = 0;
};

// Checks every colour against the conventions and the test's gamut.
Tally check(spz_table* table, const TableCase& tc, const Conventions& cv, const TestGamut& gamut,
            const std::vector<std::array<float, 3>>& colours) {
  Tally r;
  for (const auto& rgb : colours) {
    ++r.colours;
    spz_spectrum s;
    const int status = spz_fetch(table, rgb.data(), &s);
    const std::vector<float> v = samples(s);
    for (float x : v)
      if (!(x >= 0) || (tc.reflectance && x > 1)) ++r.out_of_bounds;
    const Xyz t = cv.target(rgb.data());
    if (t == Xyz{}) {  // black: exact, the zero spectrum
      if (status != SPZ_EXACT || cv.xyz_of(v).max_abs() != 0) ++r.wrong_status;
      continue;
    }
    const double d = t.Y < 0 ? 1.0 : gamut.distance(t);
    const double err = test::rel_err(cv.xyz_of(v), t);
    if (d < -kBand && t.Y > 0) {
      ++r.feasible;
      if (status == SPZ_EXACT && err <= 1e-5) ++r.exact;
      if (status != SPZ_EXACT || err > 1e-5) {
        ++r.inexact;
        if (getenv("RT_DEBUG") && r.inexact < 6) {
          double mapped[3];
          const double drgb[3] = {rgb[0], rgb[1], rgb[2]};
          const int ms = table->table.view().map_into_gamut(drgb, mapped);
          printf(
              "DEBUG feasible d %.3g status %d err %.3g rgb %.9g %.9g %.9g map status %d -> %.9g "
              "%.9g %.9g\n",
              d, status, err, rgb[0], rgb[1], rgb[2], ms, mapped[0], mapped[1], mapped[2]);
        }
      }
      r.worst = std::max(r.worst, err);
    } else if (d > kBand) {
      if (status == SPZ_MAPPED)
        ++r.mapped;
      else if (status == SPZ_NEGATIVE)
        ++r.negative;
      else if (status == SPZ_EXACT && err <= 1e-5)
        ++r.snapped;  // a move below 1e-6: rounding
      else {
        ++r.wrong_status;
        if (getenv("RT_DEBUG") && r.wrong_status < 4)
          printf("DEBUG infeasible d %.3g status %d err %.3g rgb %.9g %.9g %.9g\n", d, status, err,
                 rgb[0], rgb[1], rgb[2]);
      }
      // A mapped colour's spectrum is inside the gamut (exact for the mapped colour).
      if (status == SPZ_MAPPED && gamut.distance(cv.xyz_of(v)) > 1e-6) {
        ++r.inexact;
        if (getenv("RT_DEBUG"))
          printf("DEBUG mapped outside %.3g rgb %.9g %.9g %.9g\n", gamut.distance(cv.xyz_of(v)),
                 rgb[0], rgb[1], rgb[2]);
      }
    } else {
      ++r.ambiguous;
      if (status == SPZ_EXACT && err > 1e-5) {
        ++r.inexact;
        if (getenv("RT_DEBUG"))
          printf(
              "DEBUG ambiguous %s d %.3g err %.3g rgb %.9g %.9g %.9g Y %.3g got %.3g %.3g %.3g\n",
              tc.name.c_str(), d, err, rgb[0], rgb[1], rgb[2], t.Y, cv.xyz_of(v).X, cv.xyz_of(v).Y,
              cv.xyz_of(v).Z);
      }
    }
  }
  return r;
}

class RtTable : public testing::TestWithParam<TableCase> {};

// The Done-when check: >= 100 000 colours per space and mode, all exact where feasible.
TEST_P(RtTable, EveryFeasibleColourIsExactAndBounded) {
  const TableCase& tc = GetParam();
  spz_table* table = load(tc.name);
  ASSERT_NE(table, nullptr);
  // The table's matrix is the space's (measured by OCIO in float, white snapped).
  double m[9];
  spz_table_rgb_to_xyz(table, m);
  for (int k = 0; k < 9; ++k) {
    EXPECT_NEAR(m[k], tc.rgb_to_xyz[k / 3][k % 3], 2e-5) << k;
  }
  EXPECT_EQ(spz_table_mode(table), tc.reflectance ? 1 : 0);
  const Conventions cv(tc.reflectance, tc.rgb_to_xyz);
  const TestGamut gamut(cv.w, tc.reflectance);
  const Tally r = check(table, tc, cv, gamut, colours_of(tc, cv, gamut, 100000));
  std::printf(
      "  %s: %zu colours; feasible %zu, exact %zu (%.4f%% of the feasible volume sampled), "
      "worst relative XYZ %.2g; mapped %zu, negative luminance %zu, on the boundary to 1e-8 %zu\n",
      tc.name.c_str(), r.colours, r.feasible, r.exact,
      100.0 * r.exact / std::max<std::size_t>(r.feasible, 1), r.worst, r.mapped, r.negative,
      r.ambiguous);
  EXPECT_GE(r.colours, 100000u);
  EXPECT_GT(r.feasible, 30000u);
  EXPECT_EQ(r.exact, r.feasible);
  EXPECT_EQ(r.inexact, 0u);
  EXPECT_EQ(r.out_of_bounds, 0u);
  EXPECT_EQ(r.wrong_status, 0u);
  EXPECT_LE(r.worst, 1e-5);
  spz_table_free(table);
}

// The share of the RGB unit cube a table is exact for, as `spectralize table -v` states it
// (the fixture keeps each table's report), is the share of the cube's 32^3 cell centres inside
// the test's own gamut; colours within 1e-6 of its boundary may count either way.
TEST_P(RtTable, TheExactShareOfTheCubeItStatesIsTheGamutsShare) {
  const TableCase& tc = GetParam();
  std::ifstream log(std::string(SPECTRALIZE_RT_TABLES) + "/" + tc.name + ".log");
  const std::string text((std::istreambuf_iterator<char>(log)), std::istreambuf_iterator<char>());
  const std::string key = "exact for ";
  const std::size_t at = text.find(key);
  ASSERT_NE(at, std::string::npos) << text;
  const double stated = std::stod(text.substr(at + key.size())) / 100;
  EXPECT_NE(
      text.find(tc.reflectance ? "inside the reflectance solid" : "inside the spectral locus"),
      std::string::npos)
      << text;
  const Conventions cv(tc.reflectance, tc.rgb_to_xyz);
  const TestGamut gamut(cv.w, tc.reflectance);
  const int n = 32;
  std::size_t inside = 0, near = 0;
  for (int b = 0; b < n; ++b)
    for (int g = 0; g < n; ++g)
      for (int r = 0; r < n; ++r) {
        const float rgb[3] = {(r + 0.5f) / n, (g + 0.5f) / n, (b + 0.5f) / n};
        const double d = gamut.distance(cv.target(rgb));
        inside += d <= 0;
        near += std::abs(d) <= 1e-6;
      }
  const double share = static_cast<double>(inside) / (n * n * n);
  std::printf("  %s: exact for %.2f%% of the cube (stated %.1f%%; %zu centres within 1e-6)\n",
              tc.name.c_str(), 100 * share, 100 * stated, near);
  // The statement's rounding (0.05%) and the boundary's undecided centres.
  EXPECT_NEAR(stated, share, 0.0005 + static_cast<double>(near) / (n * n * n));
}

INSTANTIATE_TEST_SUITE_P(Spaces, RtTable, testing::ValuesIn(cases()),
                         [](const testing::TestParamInfo<TableCase>& i) { return i.param.name; });

// The mapping of colours outside the gamut is the core's (docs/DESIGN.md §5), to 1e-9.
TEST(RtMapping, OutsideColoursAreMappedAsTheCoreMapsThem) {
  for (const TableCase& tc : cases()) {
    SCOPED_TRACE(tc.name);
    spz_table* table = load(tc.name);
    ASSERT_NE(table, nullptr);
    const spz::TableView& view = table->table.view();
    SpectralizerSettings settings;
    settings.mode = tc.reflectance ? Mode::reflectance : Mode::emission;
    const Spectralizer sp(settings);
    const double* m = view.header().rgb_to_xyz;
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-1, 3);
    int mapped = 0;
    double worst = 0;
    for (int k = 0; k < 3000; ++k) {
      const double rgb[3] = {u(rng), u(rng), u(rng)};
      const Xyz xyz{m[0] * rgb[0] + m[1] * rgb[1] + m[2] * rgb[2],
                    m[3] * rgb[0] + m[4] * rgb[1] + m[5] * rgb[2],
                    m[6] * rgb[0] + m[7] * rgb[1] + m[8] * rgb[2]};
      const Xyz t = sp.target_of(xyz);
      if (!(t.Y > 0)) continue;
      Outcome mapping = Outcome::exact;
      const Xyz core = sp.mapped_target(t, mapping);
      const bool moved = mapping != Outcome::exact;
      double out[3];
      const int status = view.map_into_gamut(rgb, out);
      EXPECT_EQ(status == SPZ_MAPPED, moved) << rgb[0] << "," << rgb[1] << "," << rgb[2];
      if (!moved) continue;
      ++mapped;
      const Xyz back = sp.target_of({m[0] * out[0] + m[1] * out[1] + m[2] * out[2],
                                     m[3] * out[0] + m[4] * out[1] + m[5] * out[2],
                                     m[6] * out[0] + m[7] * out[1] + m[8] * out[2]});
      worst = std::max(worst, relative_error(back, core));
      // And the spectrum fetched for the colour is exact for the mapped colour.
      const float frgb[3] = {float(rgb[0]), float(rgb[1]), float(rgb[2])};
      spz_spectrum s;
      if (spz_fetch(table, frgb, &s) == SPZ_MAPPED) {
        const std::vector<float> v = samples(s);
        const std::vector<double> d(v.begin(), v.end());
        // Float input: the mapped colour of the float RGB.
        const double fr[3] = {frgb[0], frgb[1], frgb[2]};
        double fo[3];
        view.map_into_gamut(fr, fo);
        const Xyz want = sp.target_of({m[0] * fo[0] + m[1] * fo[1] + m[2] * fo[2],
                                       m[3] * fo[0] + m[4] * fo[1] + m[5] * fo[2],
                                       m[6] * fo[0] + m[7] * fo[1] + m[8] * fo[2]});
        EXPECT_LE(relative_error(sp.weights().integrate(d), want), 1e-5);
      }
    }
    std::printf("  %s: %d mapped colours, worst relative difference to the core %.2g\n",
                tc.name.c_str(), mapped, worst);
    EXPECT_GT(mapped, 500);
    EXPECT_LE(worst, 1e-9);
    spz_table_free(table);
  }
}

// The documented grid: nodes at ((i/24)^2, ...) on [0, 1]. Every node's spectrum is the
// model's own for its colour, solved here directly; a point inside a cell is the blend of its
// Kuhn simplex's corners with the weights written out here (sorted fractional coordinates).
// A transposed weight, a perturbed node or a table of other settings fails this.
void expect_model_nodes(spz_table* table, const Spectralizer& sp, const Conventions& cv,
                        const TestGamut& gamut, int count, double* worst_out) {
  const double* m = table->table.view().header().rgb_to_xyz;
  auto spectrum_of = [&](const std::array<double, 3>& rgb) {
    const Xyz xyz{m[0] * rgb[0] + m[1] * rgb[1] + m[2] * rgb[2],
                  m[3] * rgb[0] + m[4] * rgb[1] + m[5] * rgb[2],
                  m[6] * rgb[0] + m[7] * rgb[1] + m[8] * rgb[2]};
    return sp.spectralize(xyz).values;
  };
  auto node = [](int k) {
    const double x = k / 24.0;
    return double(float(x * x));  // the table's positions, (k/24)^2 rounded to float
  };
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> index(1, 22);
  std::uniform_real_distribution<double> u(0, 1);
  double worst = 0;
  for (int c = 0; c < count;) {
    const int i[3] = {index(rng), index(rng), index(rng)};
    double f[3] = {u(rng), u(rng), u(rng)};
    std::array<double, 3> lo, hi, p;
    for (int a = 0; a < 3; ++a)
      lo[a] = node(i[a]), hi[a] = node(i[a] + 1), p[a] = lo[a] + f[a] * (hi[a] - lo[a]);
    // Cells wholly inside the gamut (every corner: it is convex); wide gamuts' cube corners
    // are not.
    bool inside = true;
    for (int k = 0; k < 8; ++k) {
      const float q[3] = {float(k & 1 ? hi[0] : lo[0]), float(k & 2 ? hi[1] : lo[1]),
                          float(k & 4 ? hi[2] : lo[2])};
      inside = inside && gamut.distance(cv.target(q)) < -1e-6;
    }
    if (!inside) continue;
    ++c;
    const float rgb[3] = {float(p[0]), float(p[1]), float(p[2])};
    for (int a = 0; a < 3; ++a) f[a] = (double(rgb[a]) - lo[a]) / (hi[a] - lo[a]);
    // Kuhn: order the axes by decreasing fraction; corners walk along them.
    int order[3] = {0, 1, 2};
    std::sort(order, order + 3, [&](int a, int b) { return f[a] > f[b]; });
    std::vector<double> want(81, 0.0);
    std::array<double, 3> corner = lo;
    const double w[4] = {1 - f[order[0]], f[order[0]] - f[order[1]], f[order[1]] - f[order[2]],
                         f[order[2]]};
    for (int k = 0; k < 4; ++k) {
      const std::vector<double> s = spectrum_of(corner);
      for (int b = 0; b < 81; ++b) want[b] += w[k] * s[b];
      if (k < 3) corner[order[k]] = hi[order[k]];
    }
    spz_spectrum s;
    EXPECT_EQ(spz_fetch(table, rgb, &s), SPZ_EXACT);
    const std::vector<float> got = samples(s);
    const std::vector<double> g(got.begin(), got.end());
    worst = std::max(worst, test::rel_err(g, want));
    // The node itself.
    const std::array<double, 3> n = {lo[0], lo[1], lo[2]};
    const float nrgb[3] = {float(n[0]), float(n[1]), float(n[2])};
    spz_fetch(table, nrgb, &s);
    const std::vector<float> ng = samples(s);
    worst =
        std::max(worst, test::rel_err(std::vector<double>(ng.begin(), ng.end()), spectrum_of(n)));
  }
  *worst_out = worst;
}

TEST(RtNodes, NodesAreTheModelsSpectraAndCellsBlendThemByKuhnWeights) {
  for (const char* name : {"srgb_reflectance", "rec2020_reflectance"}) {
    SCOPED_TRACE(name);
    spz_table* table = load(name);
    ASSERT_NE(table, nullptr);
    SpectralizerSettings settings;
    settings.mode = Mode::reflectance;
    const Spectralizer sp(settings);
    const Conventions cv(
        true, name == std::string("srgb_reflectance") ? test::kRec709ToXyz : test::kRec2020ToXyz);
    const TestGamut gamut(cv.w, true);
    double worst = 1;
    expect_model_nodes(table, sp, cv, gamut, 60, &worst);
    std::printf("  %s: blends of directly solved nodes, worst relative difference %.2g\n", name,
                worst);
    EXPECT_LE(worst, 2e-6);
    spz_table_free(table);
  }
}

std::string read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

void rewrite_checksum(std::string& bytes) {
  std::memset(bytes.data() + 24, 0, 8);
  const std::uint64_t sum = spz::detail::table_checksum(
      reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size());
  std::memcpy(bytes.data() + 24, &sum, 8);
}

std::string scratch_dir() {
  const fs::path dir = fs::temp_directory_path() / ("spz-rt-test-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir.string();
}

// Meta-test: the checks above fail on a table made with other settings than those it is
// checked against; a table with its nodes perturbed (its checksum made valid again) no longer
// even loads: its spectra do not reproduce their positions (the loader's own check of meaning).
TEST(RtNodes, APerturbedNodeOrAStaleTableFailsTheChecks) {
  std::string bytes = read_bytes(table_path("srgb_reflectance"));
  ASSERT_GT(bytes.size(), 4096u);
  spz_file_header h;
  std::memcpy(&h, bytes.data(), sizeof h);
  const std::size_t slots = h.sections[SPZ_SECTION_SPECTRA].count / h.bands;
  float* spectra = reinterpret_cast<float*>(bytes.data() + h.sections[SPZ_SECTION_SPECTRA].offset);
  for (std::size_t slot = 0; slot < slots; ++slot)
    for (std::uint32_t k = 30; k < 40; ++k) spectra[slot * h.bands + k] *= 0.99f;  // every node
  rewrite_checksum(bytes);
  const std::string path = scratch_dir() + "/perturbed.spztab";
  std::ofstream(path, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
  char error[512];
  spz_table* perturbed = spz_table_load(path.c_str(), error, sizeof error);
  EXPECT_EQ(perturbed, nullptr) << "a table whose spectra are 1% off loads";
  EXPECT_NE(std::string(error).find("does not reproduce the colour of its position"),
            std::string::npos)
      << error;
  spz_table_free(perturbed);
  const TableCase srgb = cases()[0];
  const Conventions cv(true, srgb.rgb_to_xyz);
  const TestGamut gamut(cv.w, true);
  // A stale table: Rec.2020's checked as sRGB; and sRGB's checked under illuminant A.
  spz_table* rec2020 = load("rec2020_reflectance");
  ASSERT_NE(rec2020, nullptr);
  EXPECT_GT(check(rec2020, srgb, cv, gamut, colours_of(srgb, cv, gamut, 2000)).inexact, 100u);
  spz_table_free(rec2020);
  spz_table* table = load("srgb_reflectance");
  const Conventions under_a(true, srgb.rgb_to_xyz, "A");
  const TestGamut gamut_a(under_a.w, true);
  EXPECT_GT(check(table, srgb, under_a, gamut_a, colours_of(srgb, under_a, gamut_a, 2000)).inexact,
            100u);
  spz_table_free(table);
  fs::remove_all(fs::path(path).parent_path());
}

// Lights are scale-free: any brightness, the same spectrum times it.
TEST(RtEval, EmissionScalesWithTheColour) {
  spz_table* table = load("srgb_emission");
  ASSERT_NE(table, nullptr);
  const float rgb[3] = {0.3f, 0.6f, 0.2f};
  spz_spectrum a, b;
  ASSERT_EQ(spz_fetch(table, rgb, &a), SPZ_EXACT);
  const float bright[3] = {3000.f, 6000.f, 2000.f};
  ASSERT_EQ(spz_fetch(table, bright, &b), SPZ_EXACT);
  for (float nm = 380; nm <= 780; nm += 7) {
    EXPECT_NEAR(spz_eval(&b, nm), 1e4f * spz_eval(&a, nm), 2e-5f * 1e4f * spz_eval(&a, nm) + 1e-6f);
  }
  spz_table_free(table);
}

// eval is the piecewise-linear spectrum through the samples, 0 outside them; eval4 is eval.
TEST(RtEval, EvalInterpolatesTheSamplesAndIsZeroOutside) {
  for (const char* name : {"srgb_reflectance", "rec2020_reflectance", "srgb_emission"}) {
    SCOPED_TRACE(name);
    spz_table* table = load(name);
    ASSERT_NE(table, nullptr);
    float start, step;
    spz_table_wavelengths(table, &start, &step);
    EXPECT_EQ(start, 380.0f);
    EXPECT_EQ(step, 5.0f);
    EXPECT_EQ(spz_table_bands(table), 81u);
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> u(-0.2f, 1.3f);
    for (int c = 0; c < 2000; ++c) {
      const float rgb[3] = {u(rng), u(rng), u(rng)};
      spz_spectrum s;
      if (spz_fetch(table, rgb, &s) < 0) continue;
      const std::vector<float> v = samples(s);
      for (int k = 0; k + 1 < 81; k += 3) {
        const float nm = 380.0f + 5.0f * k;
        EXPECT_NEAR(spz_eval(&s, nm), v[k], 1e-6f * (1 + v[k]));
        EXPECT_NEAR(spz_eval(&s, nm + 2.0f), 0.6f * v[k] + 0.4f * v[k + 1], 1e-5f * (1 + v[k]));
      }
      EXPECT_NEAR(spz_eval(&s, 780.0f), v[80], 1e-6f * (1 + v[80]));
      EXPECT_EQ(spz_eval(&s, 379.9f), 0.0f);
      EXPECT_EQ(spz_eval(&s, 780.1f), 0.0f);
      EXPECT_EQ(spz_eval(&s, 300.0f), 0.0f);
      const float l4[4] = {379.0f, 455.5f, 612.25f, 781.0f};
      float o4[4];
      spz_eval4(&s, l4, o4);
      for (int l = 0; l < 4; ++l) {
        EXPECT_EQ(o4[l], spz_eval(&s, l4[l]));
      }
    }
    spz_table_free(table);
  }
}

// White is rho == 1 and black 0, exactly; NaN is invalid and negative luminance is refused,
// both with the zero spectrum.
TEST(RtEval, WhiteBlackNanAndNegativeLuminance) {
  spz_table* table = load("srgb_reflectance");
  ASSERT_NE(table, nullptr);
  spz_spectrum s;
  const float white[3] = {1, 1, 1}, black[3] = {0, 0, 0};
  ASSERT_EQ(spz_fetch(table, white, &s), SPZ_EXACT);
  for (float v : samples(s)) {
    EXPECT_EQ(v, 1.0f);
  }
  ASSERT_EQ(spz_fetch(table, black, &s), SPZ_EXACT);
  for (float v : samples(s)) {
    EXPECT_EQ(v, 0.0f);
  }
  const float nan[3] = {NAN, 0.5f, 0.5f}, inf[3] = {INFINITY, 0, 0}, neg[3] = {-1, -1, -1};
  EXPECT_EQ(spz_fetch(table, nan, &s), SPZ_INVALID);
  for (float v : samples(s)) {
    EXPECT_EQ(v, 0.0f);
  }
  EXPECT_EQ(spz_fetch(table, inf, &s), SPZ_INVALID);
  EXPECT_EQ(spz_fetch(table, neg, &s), SPZ_NEGATIVE);
  for (float v : samples(s)) {
    EXPECT_EQ(v, 0.0f);
  }
  spz_table_free(table);
}

// Reads are thread-safe: the same colours from four threads give the same spectra.
TEST(RtThreads, ConcurrentFetchesAgree) {
  spz_table* table = load("rec2020_reflectance");
  ASSERT_NE(table, nullptr);
  std::vector<std::array<float, 3>> colours;
  std::mt19937 rng(2);
  std::uniform_real_distribution<float> u(-0.3f, 1.3f);
  for (int k = 0; k < 4000; ++k) colours.push_back({u(rng), u(rng), u(rng)});
  std::vector<std::vector<float>> results(4, std::vector<float>(colours.size()));
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t)
    threads.emplace_back([&, t] {
      for (std::size_t k = 0; k < colours.size(); ++k) {
        spz_spectrum s;
        spz_fetch(table, colours[k].data(), &s);
        results[t][k] = spz_eval(&s, 550.0f + float(k % 50));
      }
    });
  for (auto& th : threads) th.join();
  for (int t = 1; t < 4; ++t) {
    EXPECT_EQ(results[t], results[0]);
  }
  spz_table_free(table);
}

// --- Bad files: a message naming the file and the reason, never a crash ---

void expect_refused(const std::string& path, const std::string& word) {
  char error[512] = "";
  spz_table* t = spz_table_load(path.c_str(), error, sizeof error);
  EXPECT_EQ(t, nullptr) << path;
  spz_table_free(t);
  const std::string msg = error;
  EXPECT_NE(msg.find(path), std::string::npos) << msg;
  EXPECT_NE(msg.find(word), std::string::npos) << "'" << msg << "' lacks '" << word << "'";
}

TEST(RtFile, BadFilesAreRefusedWithAMessage) {
  const std::string dir = scratch_dir();
  const std::string good = read_bytes(table_path("srgb_emission"));
  ASSERT_GT(good.size(), 4096u);
  auto write = [&](const std::string& name, const std::string& bytes) {
    const std::string p = dir + "/" + name;
    std::ofstream(p, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
    return p;
  };
  auto patched = [&](std::size_t offset, const void* value, std::size_t n, bool fix) {
    std::string b = good;
    std::memcpy(b.data() + offset, value, n);
    if (fix) rewrite_checksum(b);
    return b;
  };
  expect_refused(dir + "/missing.spztab", "No such file");
  expect_refused(dir, "directory");
  expect_refused(write("empty.spztab", ""), "truncated");
  expect_refused(write("short.spztab", good.substr(0, 100)), "truncated");
  expect_refused(write("header.spztab", good.substr(0, 1024)), "truncated");
  expect_refused(write("cut.spztab", good.substr(0, good.size() - 1)), "truncated");
  expect_refused(write("long.spztab", good + "x"), "extra bytes");
  expect_refused(write("magic.spztab", "PNG" + good.substr(3)), "not a spectralize table");
  // Another version, older (1: its checksum had a wrong FNV-1a offset basis; 2: no band
  // weights; 3: bins without their nodes) or newer.
  const std::uint32_t v1 = 1, v2 = 2, v3 = 3, v5 = 5, swapped = 0x04030201u;
  expect_refused(write("version1.spztab", patched(8, &v1, 4, true)), "make the table again");
  expect_refused(write("version2.spztab", patched(8, &v2, 4, true)), "format version 2");
  expect_refused(write("version3.spztab", patched(8, &v3, 4, true)), "make the table again");
  expect_refused(write("version5.spztab", patched(8, &v5, 4, true)), "format version 5");
  expect_refused(write("endian.spztab", patched(12, &swapped, 4, true)), "byte order");
  // Flipped bytes anywhere: the checksum.
  for (std::size_t at : {std::size_t(40), std::size_t(700), good.size() / 2, good.size() - 3}) {
    std::string b = good;
    b[at] = static_cast<char>(b[at] ^ 0x10);
    expect_refused(write("flip" + std::to_string(at) + ".spztab", b), "checksum");
  }
  // Huge counts, bad offsets, bad indices and values with a valid checksum.
  spz_file_header h;
  std::memcpy(&h, good.data(), sizeof h);
  const std::uint64_t huge = 1ull << 60, odd = h.sections[SPZ_SECTION_SPECTRA].offset + 4;
  expect_refused(write("huge.spztab",
                       patched(offsetof(spz_file_header, sections) + 16 * SPZ_SECTION_SPECTRA + 8,
                               &huge, 8, true)),
                 "outside the file");
  expect_refused(
      write("misaligned.spztab",
            patched(offsetof(spz_file_header, sections) + 16 * SPZ_SECTION_SPECTRA, &odd, 8, true)),
      "misaligned");
  const std::uint32_t nodes = 1000;
  expect_refused(write("nodes.spztab", patched(offsetof(spz_file_header, nodes), &nodes, 4, true)),
                 "section 'axis x' holds");
  const std::uint32_t bad_code = SPZ_BOUNDARY_BIT | 0x7FFFFFF0u;
  expect_refused(
      write("code.spztab", patched(h.sections[SPZ_SECTION_CELLS].offset, &bad_code, 4, true)),
      "has code");
  const float nan = NAN;
  expect_refused(
      write("nan.spztab", patched(h.sections[SPZ_SECTION_SPECTRA].offset + 8, &nan, 4, true)),
      "not in [0, sample_bound");
  const std::uint32_t bad_slot = 0x7FFFFFFEu;
  expect_refused(
      write("slot.spztab", patched(h.sections[SPZ_SECTION_NODE_SLOTS].offset +
                                       4 * (h.nodes[0] * (h.nodes[1] / 2) + h.nodes[0] / 3),
                                   &bad_slot, 4, true)),
      "not the start of one of the");
  // A slot offset inside a spectrum (not a multiple of the bands); a cell at an axis' last
  // node, where no cell is (a fetch there would read nodes of the next row).
  const std::uint32_t inside_spectrum = 81 * 7 + 1, inside_cell = 0;
  expect_refused(
      write("offset.spztab", patched(h.sections[SPZ_SECTION_NODE_SLOTS].offset +
                                         4 * (h.nodes[0] * (h.nodes[1] / 2) + h.nodes[0] / 3),
                                     &inside_spectrum, 4, true)),
      "not the start of one of the");
  expect_refused(write("edge.spztab", patched(h.sections[SPZ_SECTION_CELLS].offset +
                                                  4 * (std::uint64_t{h.nodes[0]} - 1),
                                              &inside_cell, 4, true)),
                 "the last of an axis");
  // A FIFO is refused at once, never read (it would block).
  const std::string fifo = dir + "/fifo.spztab";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  expect_refused(fifo, "not a regular file");
  fs::remove_all(dir);
}

}  // namespace
}  // namespace spectralize
