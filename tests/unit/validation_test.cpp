// The validation's measurements (figures/validation.h): its statistics (median, p95 by linear
// interpolation, max; roughness as the RMS of second differences; the edge ratio) against sums
// written out here; the measured sets against data/ read by the test itself; and validate()'s
// numbers for known patches against the test's own reference integration (docs/DESIGN.md §3)
// of the CSV reflectances: the patch's colour in the space, what is clipped, the RGB renderer's
// CIEDE2000 under another light, the lights' RGB. Every exact row reproduces every patch's D65
// colour, so a reconstruction against its own colour scores 0.

#include "figures/validation.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "colour/colour_space.h"
#include "core/colorimetry/colour_difference.h"
#include "spectralize/core/sample_weights.h"
#include "spectralize/core/spectralizer.h"
#include "spectralize/core/spectrum_model.h"
#include "test_support.h"

namespace spectralize::figures {
namespace {

// The columns of a CSV file of data/, by header name (the first column is the wavelength).
struct Csv {
  std::vector<std::string> names;  // without the wavelength column
  std::vector<double> nm;
  std::map<std::string, std::vector<double>> columns;
};

Csv read_csv(const std::string& file) {
  std::ifstream in(std::string(SPECTRALIZE_SOURCE_DIR) + "/data/" + file);
  EXPECT_TRUE(in) << file;
  Csv csv;
  std::string line, cell;
  std::getline(in, line);
  std::istringstream header(line);
  std::getline(header, cell, ',');  // wavelength_nm
  while (std::getline(header, cell, ',')) csv.names.push_back(cell);
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    std::istringstream row(line);
    std::getline(row, cell, ',');
    csv.nm.push_back(std::stod(cell));
    for (const std::string& name : csv.names) {
      std::getline(row, cell, ',');
      csv.columns[name].push_back(std::stod(cell));
    }
  }
  return csv;
}

// A CSV column at the grid's wavelengths (the 5 nm files hold every grid wavelength).
std::vector<double> on_grid(const Csv& csv, const std::string& name, const WavelengthGrid& grid) {
  std::vector<double> rho;
  for (std::size_t i = 0; i < grid.size(); ++i) {
    const auto at = std::find_if(csv.nm.begin(), csv.nm.end(),
                                 [&](double nm) { return std::abs(nm - grid[i]) < 1e-9; });
    EXPECT_NE(at, csv.nm.end()) << grid[i] << " nm";
    rho.push_back(csv.columns.at(name)[static_cast<std::size_t>(at - csv.nm.begin())]);
  }
  return rho;
}

// The validation's view of a measured reflectance, computed here: its XYZ under `light`
// relative to rho == 1 (Y = 1), by the test's own integration.
Xyz xyz_under(const std::vector<double>& rho, const std::string& light) {
  const SpectralizerSettings defaults;
  const Illuminant il = Illuminant::get(light);
  return test::reference_xyz(defaults.grid, rho, Observer::get(defaults.observer), &il.spd);
}

Xyz white_under(const std::string& light) {
  const SpectralizerSettings defaults;
  return xyz_under(std::vector<double>(defaults.grid.size(), 1.0), light);
}

// The colour an RGB texture holds for the patch (the paper's eq. 6: XYZ under D65 relative to
// the reflected white, scaled to the D65 white), in the space of matrix `to_xyz`, not clipped.
Xyz texture_rgb(const std::vector<double>& rho, const test::Mat3& to_xyz) {
  const Xyz w = white_under("D65");
  const Xyz balanced =
      hadamard(xyz_under(rho, "D65"), {kWhiteD65.X / w.X, kWhiteD65.Y / w.Y, kWhiteD65.Z / w.Z});
  return test::mul(test::inverse(to_xyz), balanced);
}

// --- The statistics ---

TEST(Spread, IsTheMedianThe95thPercentileByLinearInterpolationAndTheMax) {
  // 0, 2, ..., 20 in any order: the median is the 6th value, p95 lies half way between the
  // 10th (18) and the 11th (20) sorted values (position 0.95 x 10 = 9.5).
  const Spread s = spread({20, 4, 0, 8, 2, 16, 6, 12, 10, 14, 18});
  EXPECT_DOUBLE_EQ(s.median, 10);
  EXPECT_DOUBLE_EQ(s.p95, 19);
  EXPECT_DOUBLE_EQ(s.max, 20);
  // Four values: the median half way between the middle two (position 1.5), p95 at 2.85.
  const Spread even = spread({4, 1, 3, 2});
  EXPECT_DOUBLE_EQ(even.median, 2.5);
  EXPECT_NEAR(even.p95, 3.85, 1e-12);
  EXPECT_DOUBLE_EQ(even.max, 4);
  // One value is all three; none is zeros.
  const Spread one = spread({7});
  EXPECT_EQ(one.median, 7);
  EXPECT_EQ(one.p95, 7);
  EXPECT_EQ(one.max, 7);
  const Spread none = spread({});
  EXPECT_EQ(none.median, 0);
  EXPECT_EQ(none.p95, 0);
  EXPECT_EQ(none.max, 0);
}

TEST(Spread, OfIdenticalDifferencesIsThatDifference) {
  // A spectrum against itself: every difference 0, so every statistic 0.
  const Spread zero = spread(std::vector<double>(24, 0.0));
  EXPECT_EQ(zero.median, 0);
  EXPECT_EQ(zero.p95, 0);
  EXPECT_EQ(zero.max, 0);
}

TEST(Roughness, IsZeroOnALineAndTheSecondDifferenceOnAParabola) {
  std::vector<double> line, parabola, zigzag;
  for (int i = 0; i < 81; ++i) {
    line.push_back(0.1 + 0.01 * i);
    parabola.push_back(0.5 * i * i);       // second difference 1 everywhere
    zigzag.push_back(i % 2 ? -1.0 : 1.0);  // second difference +-4
  }
  EXPECT_NEAR(roughness(line), 0, 1e-12);
  EXPECT_NEAR(roughness(parabola), 1, 1e-9);
  EXPECT_NEAR(roughness(zigzag), 4, 1e-12);
  // The RMS is over the interior samples: one bump of second differences 1, -2, 1 among 79.
  std::vector<double> bump(81, 0.0);
  bump[40] = 1;
  EXPECT_NEAR(roughness(bump), std::sqrt((1.0 + 4.0 + 1.0) / 79.0), 1e-12);
  // Too short for a second difference.
  EXPECT_EQ(roughness({1.0, 5.0}), 0);
}

TEST(EdgeRatio, IsThePeakWithin20nmOfAnEndOverTheMeanOf400To700nm) {
  const WavelengthGrid grid = SpectralizerSettings{}.grid;  // 380..780 nm at 5 nm
  ASSERT_EQ(grid.size(), 81u);
  const std::vector<double> flat(grid.size(), 0.4);
  EXPECT_NEAR(edge_ratio(grid, flat), 1, 1e-12);
  auto with = [&](double nm, double value) {
    std::vector<double> x(grid.size(), 1.0);
    x[static_cast<std::size_t>(std::lround((nm - 380) / 5))] = value;
    return x;
  };
  // 400 nm is both within 20 nm of the start and in 400..700 nm (61 samples).
  EXPECT_NEAR(edge_ratio(grid, with(400, 3)), 3 / (63.0 / 61), 1e-12);
  // 405 nm is not near an end: the edge peak stays 1.
  EXPECT_NEAR(edge_ratio(grid, with(405, 3)), 1 / (63.0 / 61), 1e-12);
  // 760 nm is within 20 nm of the long end and outside 400..700 nm.
  EXPECT_NEAR(edge_ratio(grid, with(760, 3)), 3, 1e-12);
  EXPECT_NEAR(edge_ratio(grid, with(755, 3)), 1, 1e-12);
  // No light in 400..700 nm: no ratio.
  std::vector<double> dark(grid.size(), 0.0);
  dark.front() = 1;
  EXPECT_EQ(edge_ratio(grid, dark), 0);
}

// --- The measured sets and the rows ---

TEST(ValidationSets, AreTheColorCheckerAndAmpasColumnsOfDataOnTheGrid) {
  const std::vector<PatchSet> sets = validation_sets();
  ASSERT_EQ(sets.size(), 2u);
  EXPECT_EQ(sets[0].name, "ColorChecker");
  EXPECT_EQ(sets[0].count, 24u);
  EXPECT_EQ(sets[1].count, 190u);
  const std::vector<std::vector<MeasuredPatch>> loaded = load_validation_sets();
  ASSERT_EQ(loaded.size(), 2u);
  const WavelengthGrid grid = SpectralizerSettings{}.grid;
  for (std::size_t k = 0; k < sets.size(); ++k) {
    SCOPED_TRACE(sets[k].file);
    const Csv csv = read_csv(sets[k].file);
    ASSERT_EQ(loaded[k].size(), sets[k].count);
    ASSERT_EQ(csv.names.size(), sets[k].count);
    for (std::size_t i = 0; i < loaded[k].size(); ++i) {
      EXPECT_EQ(loaded[k][i].name, csv.names[i]);
      ASSERT_EQ(loaded[k][i].rho.size(), grid.size());
      const std::vector<double> want = on_grid(csv, csv.names[i], grid);
      for (std::size_t j = 0; j < grid.size(); ++j)
        ASSERT_NEAR(loaded[k][i].rho[j], want[j], 1e-12) << csv.names[i] << " at " << grid[j];
    }
  }
}

TEST(ValidationConfigs, NameEachRowOnceAndMarkTheDefaultModel) {
  const std::vector<ValidationConfig> rows = validation_configs();
  std::set<std::string> names;
  int defaults = 0;
  bool reference_seen = false;
  for (const ValidationConfig& r : rows) {
    EXPECT_TRUE(names.insert(r.name).second) << "twice: " << r.name;
    EXPECT_TRUE(r.make) << r.name;
    if (r.name.find("(default") != std::string::npos) {
      ++defaults;
      EXPECT_EQ(r.model, default_model_name()) << r.name;
    }
    // The registered models first, then the reference lines (no model, no lights).
    if (r.model.empty()) {
      reference_seen = true;
    } else {
      EXPECT_FALSE(reference_seen) << r.name << " after a reference line";
      EXPECT_NO_THROW(find_model(r.model)) << r.name;
      EXPECT_TRUE(r.exact) << r.name;  // a model reproduces every colour of the solid
    }
  }
  EXPECT_EQ(defaults, 1);
  EXPECT_TRUE(reference_seen);
  EXPECT_EQ(validation_lights(),
            (std::vector<std::string>{"A", "FL11", "FL2", "LED-B3", "HP1", "D50"}));
  EXPECT_EQ(validation_spaces(),
            (std::vector<std::string>{"Linear Rec.709 (sRGB)", "Linear Rec.2020"}));
}

// The rows that are registered models reconstruct a patch's colour exactly: the reflectance's
// XYZ by the test's integration is the white-balanced input (docs/DESIGN.md §3), within 0 <= rho
// <= 1; the exemplar row, cross-validated, does not give back the patch's own measurement.
TEST(ValidationConfigs, ModelRowsReproduceAPatchsColourWithoutItsMeasurement) {
  const ColourSpaces spaces = ColourSpaces::load();
  const std::string space = "Linear Rec.709 (sRGB)";
  const ColourTransform to_xyz = spaces.to_xyz(space);
  SpectralizerSettings settings;
  settings.mode = Mode::reflectance;
  const Spectralizer protocol(settings);
  const std::vector<std::vector<MeasuredPatch>> sets = load_validation_sets();
  const MeasuredPatch& patch = sets[0][1];  // light skin: inside sRGB
  const Xyz rgb = texture_rgb(patch.rho, test::kRec709ToXyz);
  ASSERT_TRUE(rgb.X > 0 && rgb.X < 1 && rgb.Y > 0 && rgb.Y < 1 && rgb.Z > 0 && rgb.Z < 1);
  const Xyz input = test::mul(test::kRec709ToXyz, rgb);
  const Xyz w = white_under("D65");
  const Xyz target = hadamard(input, {w.X / kWhiteD65.X, w.Y / kWhiteD65.Y, w.Z / kWhiteD65.Z});
  for (const ValidationConfig& row : validation_configs()) {
    if (row.model.empty()) continue;
    SCOPED_TRACE(row.name);
    const auto r = row.make(RowContext{space, &to_xyz, &protocol, &sets});
    const Reconstructed s = r->reconstruct(0, 1, {rgb.X, rgb.Y, rgb.Z}, input);
    EXPECT_EQ(s.status, "ok");
    ASSERT_EQ(s.values.size(), settings.grid.size());
    const Xyz got = xyz_under(s.values, "D65");
    // Float tables (the render-time row) hold 1e-5; the solvers 1e-9.
    EXPECT_LT(test::rel_err(got, target), 2e-5);
    for (double v : s.values) {
      EXPECT_GE(v, -1e-6);
      EXPECT_LE(v, 1 + 1e-6);
    }
    // A metamer, not the measurement (the exemplar row is scored with the other set's
    // exemplars): some sample differs.
    EXPECT_GT(test::rel_err(s.values, patch.rho), 1e-3);
  }
}

// --- validate() ---

const Validation& results() {
  static const Validation v = validate(ColourSpaces::load());
  return v;
}

// Views, not strings: a temporary string argument would make the returned reference (into the
// results) look dangling to GCC 13+'s -Wdangling-reference.
const ConfigResult& config(std::string_view name_start, std::string_view space) {
  for (const ConfigResult& c : results().configs)
    if (c.config.name.rfind(name_start, 0) == 0 && c.space == space) return c;
  ADD_FAILURE() << "no configuration " << name_start << " in " << space;
  return results().configs.front();
}

const std::map<std::string, test::Mat3> kSpaces = {{"Linear Rec.709 (sRGB)", test::kRec709ToXyz},
                                                   {"Linear Rec.2020", test::kRec2020ToXyz}};

TEST(ValidateSlow, EveryExactRowScoresZeroAgainstTheColourItWasGiven) {
  const Validation& v = results();
  ASSERT_EQ(v.configs.size(), validation_configs().size() * validation_spaces().size());
  for (const ConfigResult& c : v.configs) {
    SCOPED_TRACE(c.config.name + " / " + c.space);
    ASSERT_TRUE(c.available) << c.error;
    ASSERT_EQ(c.sets.size(), 2u);
    for (const PatchSetResult& r : c.sets) {
      ASSERT_EQ(r.patches.size(), r.set.count);
      std::size_t clipped = 0;
      double max_d65 = 0;
      for (const PatchResult& p : r.patches) {
        ASSERT_EQ(p.delta_e.size(), validation_lights().size());
        clipped += p.clipped;
        max_d65 = std::max(max_d65, p.delta_e_d65);
        if (!c.config.exact) continue;
        // The round trip: the spectrum against the colour it was made from.
        EXPECT_LT(p.delta_e_d65, 1e-3) << p.name;
        EXPECT_LT(p.relative_xyz_error, 2e-5) << p.name;
        // Unclipped, that colour is the measurement's: a metamer under D65.
        if (!p.clipped) {
          EXPECT_LT(p.delta_e_d65_measured, 5e-3) << p.name;
        }
      }
      // The summary is of these patches.
      EXPECT_EQ(r.summary.clipped, clipped);
      EXPECT_EQ(r.summary.delta_e_d65.max, max_d65);
      ASSERT_EQ(r.summary.delta_e.size(), validation_lights().size());
      for (std::size_t k = 0; k < validation_lights().size(); ++k) {
        std::vector<double> de;
        for (const PatchResult& p : r.patches) de.push_back(p.delta_e[k]);
        std::sort(de.begin(), de.end());
        EXPECT_EQ(r.summary.delta_e[k].max, de.back());
        const double median =
            de.size() % 2 ? de[de.size() / 2] : (de[de.size() / 2 - 1] + de[de.size() / 2]) / 2;
        EXPECT_NEAR(r.summary.delta_e[k].median, median, 1e-12);
      }
    }
  }
}

// A patch's colour, its clipping and its measured roughness, from data/ by the test's own
// integration, in both spaces; the same for every row (the colour is the input, not the output).
TEST(ValidateSlow, PatchColoursAreTheMeasurementsUnderD65InTheSpace) {
  const WavelengthGrid grid = SpectralizerSettings{}.grid;
  const Csv csv = read_csv("colorchecker_n_ohta_5nm.csv");
  for (const auto& [space, matrix] : kSpaces) {
    SCOPED_TRACE(space);
    const ConfigResult& c = config("natural", space);
    const PatchSetResult& checker = c.sets.at(0);
    ASSERT_EQ(checker.patches.size(), csv.names.size());
    std::size_t clipped = 0;
    for (std::size_t i = 0; i < csv.names.size(); ++i) {
      const PatchResult& p = checker.patches[i];
      const std::vector<double> rho = on_grid(csv, csv.names[i], grid);
      const Xyz rgb = texture_rgb(rho, matrix);
      const bool outside =
          std::min({rgb.X, rgb.Y, rgb.Z}) < 0 || std::max({rgb.X, rgb.Y, rgb.Z}) > 1;
      clipped += outside;
      EXPECT_EQ(p.name, csv.names[i]);
      EXPECT_EQ(p.clipped, outside) << p.name;
      for (int k = 0; k < 3; ++k)
        EXPECT_NEAR(p.rgb[k], std::clamp(rgb[k], 0.0, 1.0), 2e-5) << p.name;
      // The measurement's own roughness: RMS of x[i-1] - 2 x[i] + x[i+1].
      double s = 0;
      for (std::size_t j = 1; j + 1 < rho.size(); ++j)
        s += std::pow(rho[j - 1] - 2 * rho[j] + rho[j + 1], 2);
      EXPECT_NEAR(p.roughness_measured, std::sqrt(s / static_cast<double>(rho.size() - 2)), 1e-12);
    }
    // The chart's cyan is outside sRGB and inside Rec.2020.
    if (space == "Linear Rec.709 (sRGB)") {
      EXPECT_GE(clipped, 1u);
    } else {
      EXPECT_EQ(clipped, 0u);
    }
  }
}

// The RGB renderer shows a patch under a light as its RGB times the light's RGB, both in the
// fixed D65 calibration; the truth is the measurement under that light. Both written out here.
TEST(ValidateSlow, RgbRendererErrorIsItsProductAgainstTheMeasurementUnderTheLight) {
  const Csv csv = read_csv("colorchecker_n_ohta_5nm.csv");
  const WavelengthGrid grid = SpectralizerSettings{}.grid;
  const Xyz w65 = white_under("D65");
  const Xyz calibration{kWhiteD65.X / w65.X, kWhiteD65.Y / w65.Y, kWhiteD65.Z / w65.Z};
  const std::vector<std::string> lights = validation_lights();
  for (const RgbBaseline& b : results().baselines) {
    if (b.set != "ColorChecker") continue;
    SCOPED_TRACE(b.space);
    const test::Mat3 m = kSpaces.at(b.space), inv = test::inverse(m);
    ASSERT_EQ(b.delta_e.size(), lights.size());
    for (std::size_t j = 0; j < lights.size(); ++j)
      for (const std::size_t i : {std::size_t{0}, std::size_t{13}, std::size_t{17}}) {
        const std::vector<double> rho = on_grid(csv, csv.names[i], grid);
        const Xyz white = hadamard(white_under(lights[j]), calibration);
        const Xyz light_rgb = test::mul(inv, white);
        Xyz rgb = texture_rgb(rho, m);
        for (int c = 0; c < 3; ++c) rgb[c] = std::clamp(rgb[c], 0.0, 1.0);
        const Xyz shown = test::mul(m, hadamard(rgb, light_rgb));
        const Xyz truth = hadamard(xyz_under(rho, lights[j]), calibration);
        const double want = delta_e_2000(to_lab(shown, white), to_lab(truth, white));
        EXPECT_NEAR(b.delta_e[j][i], want, 1e-3) << csv.names[i] << " under " << lights[j];
      }
    // Under D50, close to D65, the RGB renderer is nearly right; under FL11 it is not.
    EXPECT_LT(b.spreads[5].median, b.spreads[1].median);
  }
}

// Each model row's lights: the CIE illuminant's SPD on the grid at Y = 1, as RGB in the space;
// the reconstruction reproduces its colour.
TEST(ValidateSlow, LightsAreTheIlluminantsColourInTheSpaceAndAreReproduced) {
  const SpectralizerSettings defaults;
  const Observer& obs = Observer::get(defaults.observer);
  for (const auto& [space, matrix] : kSpaces) {
    const ConfigResult& c = config("natural", space);
    ASSERT_EQ(c.lights.size(), 3u);
    for (const LightResult& l : c.lights) {
      SCOPED_TRACE(space + " / " + l.name);
      // The illuminant at the grid's (whole) wavelengths, as emission at Y = 1.
      const Illuminant il = Illuminant::get(l.name);
      std::vector<double> spd;
      for (std::size_t i = 0; i < defaults.grid.size(); ++i)
        spd.push_back(il.spd[static_cast<std::size_t>(std::lround(defaults.grid[i] - 360))]);
      const Xyz xyz = test::reference_xyz(defaults.grid, spd, obs, nullptr);
      const Xyz rgb = test::mul(test::inverse(matrix), (1 / xyz.Y) * xyz);
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(l.rgb[k], rgb[k], 2e-5);
      EXPECT_EQ(l.in_gamut, rgb.X >= 0 && rgb.Y >= 0 && rgb.Z >= 0);
      if (l.status == "ok") {
        EXPECT_LT(l.delta_e_light, 1e-3);
      }
      EXPECT_GE(l.checker_delta_e_max, l.checker_delta_e_median);
    }
  }
  // Reference lines make no lights.
  for (const ConfigResult& c : results().configs)
    if (c.config.model.empty()) {
      EXPECT_TRUE(c.lights.empty()) << c.config.name;
    }
}

}  // namespace
}  // namespace spectralize::figures
