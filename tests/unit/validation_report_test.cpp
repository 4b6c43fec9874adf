// The validation's reports (figures/validation_report.h) hold the numbers they are given: the
// JSON keeps every figure under its light's name (the RGB renderer's [light][patch] as per patch,
// per light), the filter only for a model that reads one, the error of an unavailable row; the
// Markdown tables have as many cells in every row as in their header, and show the given
// numbers at their stated precision. The results are made up here, not measured.

#include "figures/validation_report.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "file_test_support.h"
#include "spectralize/core/error.h"
#include "spectralize/core/spectrum_model.h"
#include "test_support.h"

namespace spectralize::figures {
namespace {

const std::vector<std::string> kLights = {"A", "FL11", "FL2", "LED-B3", "HP1", "D50"};

// A patch whose numbers are distinct: base + small offsets.
PatchResult patch(const std::string& name, double base, bool clipped) {
  PatchResult p;
  p.name = name;
  p.rgb = {base, base + 0.1, base + 0.2};
  p.clipped = clipped;
  p.status = clipped ? "out_of_gamut" : "ok";
  p.delta_e_d65 = base * 1e-9;
  p.delta_e_d65_measured = base + 0.01;
  for (std::size_t k = 0; k < kLights.size(); ++k) p.delta_e.push_back(base + 1 + k);
  p.rmse = base + 0.02;
  p.roughness = base + 0.03;
  p.roughness_measured = base + 0.04;
  p.edge_ratio = base + 0.05;
  p.edge_ratio_measured = base + 0.06;
  p.relative_xyz_error = 3e-13;
  p.rho_min = 0.011;
  p.rho_max = 0.987;
  return p;
}

ConfigResult model_config(const std::string& name, const std::string& model,
                          const std::string& filter) {
  ConfigResult c;
  c.config.name = name;
  c.config.model = model;
  c.config.filter = EdgeFilter::parse(filter);
  c.space = "Linear Rec.709 (sRGB)";
  c.seconds = 0.25;
  PatchSetResult r;
  r.set = validation_sets().at(0);
  r.patches = {patch("dark skin", 0.2, false), patch("cyan", 0.4, true)};
  ValidationSummary& s = r.summary;
  s.delta_e_d65 = {0.123, 0.456, 0.789};
  for (std::size_t k = 0; k < kLights.size(); ++k) s.delta_e.push_back({1.0 + k, 2.0 + k, 3.0 + k});
  s.mean_rmse = 0.01234;
  s.mean_roughness = 0.00567;
  s.mean_roughness_measured = 0.00891;
  s.max_relative_xyz_error = 4e-13;
  s.max_edge_ratio = 1.75;
  s.max_edge_ratio_measured = 2.25;
  s.rho_min = 0.011;
  s.rho_max = 0.987;
  s.clipped = 1;
  c.sets.push_back(r);
  LightResult l;
  l.name = "A";
  l.rgb = {1.25, 0.95, -0.05};
  l.in_gamut = false;
  l.status = "ok";
  l.delta_e_light = 2e-7;
  l.rmse = 0.0321;
  l.roughness = 0.0012;
  l.roughness_real = 0.0034;
  l.edge_ratio = 1.5;
  l.relative_xyz_error = 1e-12;
  l.checker_delta_e_median = 0.345;
  l.checker_delta_e_max = 1.23;
  c.lights.push_back(l);
  return c;
}

Validation made_up() {
  Validation v;
  v.configs.push_back(model_config("paper, filter 0.5", "paper", "0.5"));
  ConfigResult smooth = model_config("smooth", "smooth", "0.5");
  smooth.space = "Linear Rec.2020";
  v.configs.push_back(smooth);
  ConfigResult broken;
  broken.config.name = "broken row";
  broken.space = "Linear Rec.709 (sRGB)";
  broken.available = false;
  broken.error = "no table for this space";
  v.configs.push_back(broken);
  RgbBaseline b;
  b.space = "Linear Rec.709 (sRGB)";
  b.set = "ColorChecker";
  b.patches = {"dark skin", "cyan"};
  for (std::size_t k = 0; k < kLights.size(); ++k) {
    b.delta_e.push_back({10.0 + k, 20.0 + k});  // [light][patch]
    b.spreads.push_back({0.5 + k, 0.75 + k, 0.875 + k});
  }
  v.baselines.push_back(b);
  return v;
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// Every row of each Markdown table (runs of lines starting with '|') has as many '|' as its
// header.
void expect_rectangular_tables(const std::string& md) {
  std::size_t header = 0;
  int tables = 0;
  for (const std::string& line : lines_of(md)) {
    if (line.empty() || line[0] != '|') {
      header = 0;
      continue;
    }
    const std::size_t bars = static_cast<std::size_t>(std::count(line.begin(), line.end(), '|'));
    if (header == 0) {
      header = bars;
      ++tables;
    } else {
      EXPECT_EQ(bars, header) << line;
    }
  }
  EXPECT_GT(tables, 0);
}

bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TEST(ValidationJson, HoldsEveryNumberUnderItsLightsName) {
  const Validation v = made_up();
  const nlohmann::json doc = nlohmann::json::parse(validation_json(v));
  EXPECT_EQ(doc.at("lights").get<std::vector<std::string>>(), kLights);
  EXPECT_EQ(doc.at("grid"), SpectralizerSettings{}.grid.to_string());
  EXPECT_EQ(doc.at("data").size(), 2u);
  ASSERT_EQ(doc.at("configurations").size(), 3u);

  const nlohmann::json& paper = doc["configurations"][0];
  EXPECT_EQ(paper.at("name"), "paper, filter 0.5");
  EXPECT_EQ(paper.at("space"), "Linear Rec.709 (sRGB)");
  EXPECT_EQ(paper.at("available"), true);
  EXPECT_FALSE(paper.contains("error"));
  EXPECT_EQ(paper.at("seconds"), 0.25);
  const nlohmann::json& set = paper.at("sets").at(0);
  EXPECT_EQ(set.at("name"), "ColorChecker");
  const nlohmann::json& summary = set.at("summary");
  EXPECT_EQ(summary.at("delta_e_d65").at("median"), 0.123);
  EXPECT_EQ(summary.at("delta_e_d65").at("p95"), 0.456);
  EXPECT_EQ(summary.at("delta_e_d65").at("max"), 0.789);
  for (std::size_t k = 0; k < kLights.size(); ++k) {
    EXPECT_EQ(summary.at("delta_e").at(kLights[k]).at("median"), 1.0 + k) << kLights[k];
    EXPECT_EQ(summary.at("delta_e").at(kLights[k]).at("max"), 3.0 + k) << kLights[k];
  }
  EXPECT_EQ(summary.at("mean_rmse"), 0.01234);
  EXPECT_EQ(summary.at("mean_roughness_measured"), 0.00891);
  EXPECT_EQ(summary.at("max_edge_ratio_measured"), 2.25);
  EXPECT_EQ(summary.at("clipped_patches"), 1);
  const nlohmann::json& cyan = set.at("patches").at(1);
  EXPECT_EQ(cyan.at("name"), "cyan");
  EXPECT_EQ(cyan.at("clipped"), true);
  EXPECT_EQ(cyan.at("status"), "out_of_gamut");
  EXPECT_EQ(cyan.at("rgb").get<std::vector<double>>(),
            (std::vector<double>{0.4, 0.4 + 0.1, 0.4 + 0.2}));
  EXPECT_EQ(cyan.at("delta_e_d65_measured"), 0.4 + 0.01);
  EXPECT_EQ(cyan.at("delta_e").at("FL2"), 0.4 + 1 + 2);
  EXPECT_EQ(cyan.at("edge_ratio_measured"), 0.4 + 0.06);
  const nlohmann::json& light = paper.at("lights").at(0);
  EXPECT_EQ(light.at("name"), "A");
  EXPECT_EQ(light.at("in_gamut"), false);
  EXPECT_EQ(light.at("rgb").get<std::vector<double>>(), (std::vector<double>{1.25, 0.95, -0.05}));
  EXPECT_EQ(light.at("checker_delta_e_max"), 1.23);

  // The RGB renderer's [light][patch] is written per patch, keyed by light.
  const nlohmann::json& rgb = doc.at("rgb_renderer").at(0);
  EXPECT_EQ(rgb.at("space"), "Linear Rec.709 (sRGB)");
  for (std::size_t k = 0; k < kLights.size(); ++k) {
    EXPECT_EQ(rgb.at("patches").at(0).at("delta_e").at(kLights[k]), 10.0 + k);
    EXPECT_EQ(rgb.at("patches").at(1).at("delta_e").at(kLights[k]), 20.0 + k);
    EXPECT_EQ(rgb.at("delta_e").at(kLights[k]).at("p95"), 0.75 + k);
  }
}

TEST(ValidationJson, NamesTheFilterOnlyForModelsThatReadItAndTheErrorOfAnUnavailableRow) {
  ASSERT_TRUE(find_model("paper").uses("filter"));
  ASSERT_FALSE(find_model("smooth").uses("filter"));
  const nlohmann::json doc = nlohmann::json::parse(validation_json(made_up()));
  const nlohmann::json& c = doc.at("configurations");
  EXPECT_EQ(c[0].at("filter"), "0.5");
  EXPECT_EQ(c[1].at("filter"), "");  // the smooth model reads no filter
  EXPECT_EQ(c[2].at("filter"), "");  // a reference line: no model
  EXPECT_EQ(c[2].at("available"), false);
  EXPECT_EQ(c[2].at("error"), "no table for this space");
  EXPECT_TRUE(c[2].at("sets").empty());
  // Every column is defined.
  for (const char* key : {"delta_e_d65", "delta_e", "rmse", "roughness", "edge_ratio",
                          "relative_xyz_error", "exact", "lights"})
    EXPECT_TRUE(doc.at("definitions").contains(key)) << key;
}

TEST(SummaryTable, HasARowPerSetConfigurationAndSpaceWithTheGivenNumbers) {
  const Validation v = made_up();
  const std::string md = summary_table(v);
  expect_rectangular_tables(md);
  // The header: set, configuration, space, D65, six lights, five columns more.
  const std::vector<std::string> lines = lines_of(md);
  ASSERT_GE(lines.size(), 2u);
  EXPECT_EQ(std::count(lines[0].begin(), lines[0].end(), '|'), 1 + 4 + 6 + 5);
  // The paper row: spreads at 3 significant digits, the clipped count beside the space.
  const auto row = std::find_if(lines.begin(), lines.end(), [](const std::string& l) {
    return has(l, "| ColorChecker | paper, filter 0.5 |");
  });
  ASSERT_NE(row, lines.end()) << md;
  EXPECT_TRUE(has(*row, "| sRGB (1 clipped) | 0.123 / 0.456 / 0.789 |")) << *row;
  EXPECT_TRUE(has(*row, "| 1 / 2 / 3 | 2 / 3 / 4 |")) << *row;  // A, then FL11
  EXPECT_TRUE(has(*row, "| 6 / 7 / 8 |")) << *row;              // D50
  EXPECT_TRUE(has(*row, "| 0.0123 | 0.0057 | 1.75 | 4.0e-13 | 0.011 … 0.987 |")) << *row;
  EXPECT_TRUE(has(md, "| ColorChecker | smooth | Rec.2020 (1 clipped) |")) << md;
  EXPECT_TRUE(has(md, "| broken row | sRGB | unavailable: no table for this space |")) << md;
  EXPECT_TRUE(has(md,
                  "| ColorChecker | RGB renderer (no spectra; baseline) | sRGB | 0 by "
                  "construction | 0.5 / 0.75 / 0.875 |"))
      << md;
  // The AMPAS set has no results here: only its unavailable row.
  EXPECT_FALSE(has(md, "| AMPAS 190 | paper")) << md;
}

TEST(LightsTable, ShowsEachLightsRgbAndSaysWhenItIsOutOfGamut) {
  const Validation v = made_up();
  const std::string md = lights_table(v.configs);
  expect_rectangular_tables(md);
  EXPECT_TRUE(has(md,
                  "| paper, filter 0.5 | sRGB | A | 1.250, 0.950, -0.050 (out of gamut) | "
                  "0.0321 | 0.0012 (0.0034) | 1.50 | 2.0e-07 | 0.345 / 1.23 |"))
      << md;
  // A row per light of each configuration: two here (the unavailable row has none).
  EXPECT_EQ(lines_of(md).size(), 2u + 2u);
}

TEST(ValidationMarkdown, HasTheSummariesAndATablePerConfigurationWithItsPatches) {
  const Validation v = made_up();
  const std::string md = validation_markdown(v);
  expect_rectangular_tables(md);
  EXPECT_TRUE(has(md, "## Reflectances: summary"));
  EXPECT_TRUE(has(md, summary_table(v)));
  EXPECT_TRUE(has(md, lights_table(v.configs)));
  EXPECT_TRUE(has(md, "## paper, filter 0.5 — Linear Rec.709 (sRGB)"));
  EXPECT_TRUE(has(md, "## smooth — Linear Rec.2020"));
  EXPECT_TRUE(has(md,
                  "## broken row — Linear Rec.709 (sRGB)\n\nUnavailable: no table for this "
                  "space"));
  // A patch row: RGB at 4 decimals, the clip said, then its numbers in column order.
  EXPECT_TRUE(has(md,
                  "| cyan | 0.4000, 0.5000, 0.6000 (clipped) | out_of_gamut | 4.0e-10 | 0.41 | "
                  "1.4 | 2.4 | 3.4 | 4.4 | 5.4 | 6.4 | 0.4200 | 0.4300 (0.4400) | 0.45 | "
                  "3.0e-13 | 0.011 … 0.987 |"))
      << md;
  // The measured spectra's figures, from the first configuration's sets.
  EXPECT_TRUE(has(md, "ColorChecker measured: mean roughness 0.0089, max edge ratio 2.25")) << md;
}

TEST(RunValidation, AnOutputFolderThatCannotBeMadeIsNamed) {
  const test::TempDir dir("validation_report");
  const std::string blocker = dir / "file";
  std::ofstream(blocker) << "x";
  std::ostringstream out;
  test::expect_error_mentioning([&] { run_validation(blocker + "/sub", out); },
                                {blocker + "/sub", "cannot create"}, "a file in the way");
  EXPECT_EQ(out.str(), "");
}

}  // namespace
}  // namespace spectralize::figures
