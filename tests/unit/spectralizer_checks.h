#pragma once
// The promises every Spectralizer result keeps, shared by the paper and smooth model tests:
// exact under test_support.h's own reference integration, non-negative, a reflectance <= 1, and
// a gamut mapping that is reported and measured. Random colours of three RGB spaces.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "spectralize/core/spectralizer.h"
#include "test_support.h"

namespace spectralize::test {

// --- Helpers ---

inline Spectralizer make(Mode mode, const char* grid = "380:780:5",
                         const char* observer = "cie1931", const char* illuminant = "D65",
                         std::string model = "paper") {
  SpectralizerSettings s;
  s.model = model;
  s.grid = WavelengthGrid::parse(grid);
  s.observer = observer;
  s.mode = mode;
  s.illuminant = illuminant;
  return Spectralizer(s);
}

// The reference illuminant's SPD (reflectance) or nullptr (emission), looked up here by name.
struct Reference {
  std::unique_ptr<Illuminant> il;
  const std::vector<double>* spd() const { return il ? &il->spd : nullptr; }
};
inline Reference reference_of(const Spectralizer& sp) {
  Reference r;
  if (sp.settings().mode == Mode::reflectance)
    r.il = std::make_unique<Illuminant>(Illuminant::get(sp.settings().illuminant));
  return r;
}

// XYZ of a result's spectrum by the independent reference integration.
inline Xyz integrate(const Spectralizer& sp, const Reference& ref,
                     const std::vector<double>& values) {
  return reference_xyz(sp.settings().grid, values, Observer::get(sp.settings().observer),
                       ref.spd());
}

// The colour a spectrum must reproduce before gamut mapping: the input (emission), or the input
// white-balanced per channel from D65 to the reference white rho == 1 (reflectance, eq. 6).
// With an emission basis E (not "flat") the white is E's light: the CIE table sampled on the
// grid (1 nm table, linear between its points), integrated here.
inline Xyz expected_target(const Spectralizer& sp, const Reference& ref, const Xyz& xyz) {
  const auto& s = sp.settings();
  std::vector<double> white(s.grid.size(), 1.0);
  Xyz w;
  if (ref.il) {
    w = integrate(sp, ref, white);
  } else if (s.emission_basis != "flat") {
    const Illuminant e = Illuminant::get(s.emission_basis);
    for (std::size_t i = 0; i < white.size(); ++i) {
      const double pos = s.grid[i] - 360.0;
      const std::size_t k = static_cast<std::size_t>(pos);
      const double f = pos - static_cast<double>(k);
      white[i] = f > 0 ? (1 - f) * e.spd[k] + f * e.spd[k + 1] : e.spd[k];
    }
    w = integrate(sp, ref, white);
    w = (1.0 / w.Y) * w;
  } else {
    return xyz;
  }
  const Xyz d65 = d65_white();
  return {xyz.X * w.X / d65.X, xyz.Y * w.Y / d65.Y, xyz.Z * w.Z / d65.Z};
}

inline double xy_distance(const Xyz& a, const Xyz& b) {
  auto p = chromaticity(a), q = chromaticity(b);
  return std::hypot(p[0] - q[0], p[1] - q[1]);
}

// Tally of a batch of colours.
struct Tally {
  std::size_t ok = 0, out = 0, other = 0;
  double worst_error = 0;  // relative XYZ error vs result.target, own integration
};

// The promises for one non-black, finite, Y > 0 input (see the file comment). Tolerances:
// 1e-5 relative XYZ error is the float exactness bar (docs/DESIGN.md §3; the exact projection
// normally lands within ~1e-13); 1e-12 on the bound rho <= 1 is double rounding.
inline void check_result(const Spectralizer& sp, const Reference& ref, const Xyz& input,
                         const SpectrumResult& r, Tally& tally) {
  const bool reflectance = sp.settings().mode == Mode::reflectance;
  const Xyz want = expected_target(sp, ref, input);
  ASSERT_EQ(r.values.size(), sp.settings().grid.size());
  for (double v : r.values) {
    ASSERT_GE(v, 0.0);  // non-negative
    if (reflectance) {
      ASSERT_LE(v, 1.0 + 1e-12);  // a reflectance never exceeds 1
    }
  }
  const Xyz got = integrate(sp, ref, r.values);
  const double err = rel_err(got, r.target);
  tally.worst_error = std::max(tally.worst_error, err);
  EXPECT_LE(err, 1e-5);  // exact to its target
  if (r.status == Outcome::exact) {
    ++tally.ok;
    // ok means the input itself was reproduced: to 1e-6 relative, the tolerance below which
    // the Spectralizer treats a gamut mapping as rounding of float input (kSnapTolerance).
    EXPECT_LE(rel_err(r.target, want), 1e-6);
  } else if (r.status == Outcome::outside_locus || r.status == Outcome::outside_solid) {
    ++tally.out;
    EXPECT_GT(r.gamut_distance, 0.0);
    EXPECT_TRUE(sp.in_gamut(r.target));
    // The mapping desaturates at constant luminance, after dimming a reflectance to Y <= 1.
    EXPECT_NEAR(r.target.Y, reflectance ? std::min(want.Y, 1.0) : want.Y, 1e-9 * want.Y);
    // gamut_distance is the xy distance the colour moved (1e-9: rounding of chromaticities).
    EXPECT_NEAR(r.gamut_distance, xy_distance(want, r.target), 1e-9);
    EXPECT_FALSE(r.message.empty());  // the user is told why
  } else {
    ++tally.other;
    ADD_FAILURE() << "status " << to_string(r.status) << " for XYZ (" << input.X << ", " << input.Y
                  << ", " << input.Z << "): " << r.message;
  }
}

// Failed assertions so far in the running test.
inline int failure_count() {
  return ::testing::UnitTest::GetInstance()->current_test_info()->result()->total_part_count();
}

// Indices of the grid samples within [lo, hi] nm.
inline std::vector<std::size_t> samples_in(const WavelengthGrid& g, double lo, double hi) {
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < g.size(); ++i)
    if (g[i] >= lo - 1e-9 && g[i] <= hi + 1e-9) out.push_back(i);
  return out;
}

// Largest sample in 380-400 nm and 760-780 nm divided by the mean over 400-700 nm.
inline double edge_peak_ratio(const WavelengthGrid& g, const std::vector<double>& v) {
  double mean = 0;
  auto mid = samples_in(g, 400, 700);
  for (std::size_t i : mid) mean += v[i];
  mean /= static_cast<double>(mid.size());
  double edge = 0;
  for (std::size_t i : samples_in(g, 380, 400)) edge = std::max(edge, v[i]);
  for (std::size_t i : samples_in(g, 760, 780)) edge = std::max(edge, v[i]);
  return edge / mean;
}

struct Space {
  const char* name;
  Mat3 to_xyz;
};

inline std::vector<Space> spaces() {
  return {{"Linear Rec.709", kRec709ToXyz},
          {"Linear Rec.2020", kRec2020ToXyz},
          {"ACEScg", acescg_to_xyz_d65()}};
}

// Spectralizes `count` colours uniform in [0,1]^3 of `space`; returns the tally.
inline Tally run_random(const Spectralizer& sp, const Space& space, std::size_t count,
                        unsigned seed) {
  const Reference ref = reference_of(sp);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Tally t;
  for (std::size_t i = 0; i < count; ++i) {
    const Xyz xyz = rgb(space.to_xyz, u(rng), u(rng), u(rng));
    const SpectrumResult r = sp.spectralize(xyz);
    check_result(sp, ref, xyz, r, t);
    if (failure_count() > 20) break;  // enough to diagnose; do not flood the log
  }
  std::printf("  %-16s %-11s %zu colours: %zu ok, %zu out of gamut (%.1f%%), worst error %.1e\n",
              space.name, std::string(to_string(sp.settings().mode)).c_str(), count, t.ok, t.out,
              100.0 * static_cast<double>(t.out) / static_cast<double>(count), t.worst_error);
  return t;
}

// Expected share of out-of-gamut colours of the unit cube, from docs/DESIGN.md §5's measurements:
// every sRGB colour is a reflectance and inside the locus (its primaries are well inside);
// ~92% of the Rec.2020 cube and ~90% of the ACEScg cube are reflectances; Rec.2020's
// primaries sit on the true locus (a coarse grid's locus cuts the corners slightly), and
// ACEScg's green primary (0.165, 0.830) lies outside it.
struct Bounds {
  double lo, hi;  // fractions of the colours that may be out of gamut
};
inline Bounds expected_out(const std::string& space, Mode mode) {
  if (space == "Linear Rec.709") return {0, 0};
  if (mode == Mode::reflectance) return space == "ACEScg" ? Bounds{0.04, 0.18} : Bounds{0.03, 0.15};
  return space == "ACEScg" ? Bounds{0.0, 0.10} : Bounds{0.0, 0.05};
}

}  // namespace spectralize::test
