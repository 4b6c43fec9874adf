// The path tracer's two measurements (path_tracer/experiments.h) as a library: the reports'
// JSON holds the numbers given; a missing table, a table of the other mode and a table of the
// exemplar model (whose exemplars include the comparison's truth, docs/DESIGN.md §6) are refused
// naming the file; and a small comparison on the natural model's tables (the tracer_tables
// fixture) and the chart of testimages/ measures every pixel on a surface in all three
// differences, needs no gamut mapping, and writes its five figures at their sizes.

#include "path_tracer/experiments.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "../file_test_support.h"
#include "../test_support.h"

namespace spectralize::path_tracer {
namespace {

const std::string kChart = SPECTRALIZE_SOURCE_DIR "/testimages/colorchecker_srgb16.png";
const std::string kHdri = SPECTRALIZE_SOURCE_DIR "/testimages/hdri_forest_256x128.exr";
const std::string kReflectance = TRACER_TABLES "/srgb_reflectance_natural.spztab";
const std::string kEmission = TRACER_TABLES "/srgb_emission_natural.spztab";
const std::string kExemplar = TRACER_TABLES "/srgb_reflectance_exemplar.spztab";

DeltaEStats stats(double base) {
  return {base, base + 0.5, base + 1.25, 1000 + static_cast<std::size_t>(base)};
}

void expect_stats(const nlohmann::json& j, const DeltaEStats& s) {
  EXPECT_EQ(j.at("mean"), s.mean);
  EXPECT_EQ(j.at("p95"), s.p95);
  EXPECT_EQ(j.at("max"), s.max);
  EXPECT_EQ(j.at("pixels"), s.pixels);
}

ComparisonSetup small_comparison(const std::string& table) {
  ComparisonSetup s;
  s.texture = kChart;
  s.environment = kHdri;
  s.reflectance_table = table;
  s.illuminant = "D65";
  s.sigmoid_resolution = 8;  // the baseline's table in milliseconds
  s.render.size = 16;
  s.render.spp = {2};
  s.render.threads = 1;
  return s;
}

TEST(ExperimentsJson, ConvergenceReportHoldsEveryNumber) {
  ConvergenceReport r;
  r.points = {{4, stats(7)}, {16, stats(3)}};
  r.floor = stats(0.25);
  r.floor_spp = 16;
  r.floor_relative_xyz = 2.5e-7;
  r.mapped = 3;
  r.invalid = 1;
  r.white = {0.9, 1.25, 1.5};
  r.seconds = 4.5;
  const nlohmann::json j = nlohmann::json::parse(to_json(r));
  ASSERT_EQ(j.at("convergence").size(), 2u);
  EXPECT_EQ(j["convergence"][0].at("spp"), 4);
  expect_stats(j["convergence"][0].at("rt_vs_reference"), r.points[0].rt);
  EXPECT_EQ(j["convergence"][1].at("spp"), 16);
  expect_stats(j["convergence"][1].at("rt_vs_reference"), r.points[1].rt);
  expect_stats(j.at("floor"), r.floor);
  EXPECT_EQ(j.at("floor_spp"), 16);
  EXPECT_EQ(j.at("floor_relative_xyz"), 2.5e-7);
  EXPECT_EQ(j.at("mapped_lookups"), 3);
  EXPECT_EQ(j.at("invalid_lookups"), 1);
  EXPECT_EQ(j.at("white").get<std::vector<double>>(), (std::vector<double>{0.9, 1.25, 1.5}));
  EXPECT_EQ(j.at("seconds"), 4.5);
}

TEST(ExperimentsJson, ComparisonReportHoldsEveryNumber) {
  ComparisonReport r;
  r.illuminant = "FL11";
  r.spp = 64;
  r.rt_vs_truth = stats(1);
  r.baseline_vs_truth = stats(2);
  r.rt_vs_baseline = stats(3);
  r.mapped = 0;
  r.sigmoid_max_node_delta_e76 = 0.125;
  r.seconds = 2;
  const nlohmann::json j = nlohmann::json::parse(to_json(r));
  EXPECT_EQ(j.at("illuminant"), "FL11");
  EXPECT_EQ(j.at("spp"), 64);
  expect_stats(j.at("rt_vs_truth"), r.rt_vs_truth);
  expect_stats(j.at("baseline_vs_truth"), r.baseline_vs_truth);
  expect_stats(j.at("rt_vs_baseline"), r.rt_vs_baseline);
  EXPECT_EQ(j.at("mapped_lookups"), 0);
  EXPECT_EQ(j.at("sigmoid_max_node_delta_e76"), 0.125);
}

TEST(Experiments, AMissingTableIsRefusedNamingIt) {
  const test::TempDir dir("experiments");
  const std::string missing = dir / "none.spztab";
  test::expect_error_mentioning([&] { run_comparison(small_comparison(missing)); }, {missing},
                                "run_comparison");
  ConvergenceSetup c;
  c.texture = kChart;
  c.environment = kHdri;
  c.reflectance_table = missing;
  c.emission_table = missing;
  test::expect_error_mentioning([&] { run_convergence(c); }, {missing}, "run_convergence");
}

TEST(ExperimentTables, ATableOfTheOtherModeIsRefusedNamingIt) {
  ASSERT_TRUE(std::filesystem::exists(kEmission)) << "made by ctest's tracer_tables fixture";
  test::expect_error_mentioning([&] { run_comparison(small_comparison(kEmission)); },
                                {kEmission, "a table of emission, not of reflectance"},
                                "an emission table for the surfaces");
  ConvergenceSetup c;
  c.texture = kChart;
  c.environment = kHdri;
  c.reflectance_table = kReflectance;
  c.emission_table = kReflectance;
  test::expect_error_mentioning([&] { run_convergence(c); },
                                {kReflectance, "a table of reflectance, not of emission"},
                                "a reflectance table for the light");
}

TEST(ExperimentTables, TheExemplarModelIsRefusedForItHasSeenTheTruth) {
  ASSERT_TRUE(std::filesystem::exists(kExemplar)) << "made by ctest's tracer_tables fixture";
  test::expect_error_mentioning([&] { run_comparison(small_comparison(kExemplar)); },
                                {kExemplar, "exemplar model", "--model natural"},
                                "the exemplar model's table");
}

TEST(ExperimentTables, ASmallComparisonMeasuresTheSurfacesAndWritesItsFigures) {
  ASSERT_TRUE(std::filesystem::exists(kReflectance)) << "made by ctest's tracer_tables fixture";
  const test::TempDir dir("experiments");
  ComparisonSetup s = small_comparison(kReflectance);
  s.render.png_prefix = dir / "D65";
  const ComparisonReport r = run_comparison(s);
  EXPECT_EQ(r.illuminant, "D65");
  EXPECT_EQ(r.spp, 2);
  // The same pixels, those fully on a surface, in the three differences: most of the frame.
  EXPECT_GT(r.rt_vs_truth.pixels, 16u * 16 / 4);
  EXPECT_LT(r.rt_vs_truth.pixels, 16u * 16);
  EXPECT_EQ(r.baseline_vs_truth.pixels, r.rt_vs_truth.pixels);
  EXPECT_EQ(r.rt_vs_baseline.pixels, r.rt_vs_truth.pixels);
  for (const DeltaEStats& d : {r.rt_vs_truth, r.baseline_vs_truth, r.rt_vs_baseline}) {
    EXPECT_LE(d.mean, d.p95);
    EXPECT_LE(d.p95, d.max);
  }
  // Under D65 on shared paths and wavelengths, what differs is the spectra alone: metamers of
  // the chart's colours, near them but not equal (the full-size comparison's mean is 0.2).
  EXPECT_GT(r.rt_vs_truth.mean, 0.0);
  EXPECT_LT(r.rt_vs_truth.mean, 1.5);
  EXPECT_EQ(r.mapped, 0);  // every texel of the chart is inside the reflectance solid
  EXPECT_GT(r.sigmoid_max_node_delta_e76, 0.0);
  for (const char* name : {"_truth", "_rt", "_baseline", "_rt_dE", "_baseline_dE"}) {
    auto in = OIIO::ImageInput::open(dir / (std::string("D65") + name + ".png"));
    ASSERT_TRUE(in) << name;
    EXPECT_EQ(in->spec().width, 16) << name;
    EXPECT_EQ(in->spec().height, std::string(name).find("dE") != std::string::npos ? 96 : 16)
        << name;
  }
}

}  // namespace
}  // namespace spectralize::path_tracer
