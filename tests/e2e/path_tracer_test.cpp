// End-to-end tests of `spectralize_path_tracer` with the real `spectralize` making its inputs:
// - the render whose every RGB -> spectrum goes through spectralize::rt (4 hero wavelengths per
//   path) converges to the dense render of the spectra spectralize writes for the same images
//   (its spectral EXRs, integrated over all 471 wavelengths): the error falls as 1/sqrt(spp),
//   and rt's spectra integrated the same way reproduce the reference to float precision;
// - the comparison under illuminant A (rt, the Jakob & Hanika baseline, the measured
//   ColorChecker) gives finite, plausible numbers, recorded in the test's properties;
// - bad command lines exit 2, unusable files 1 with their name;
// - (Slow) the documents' figures are what `make docs-renders` makes, byte for byte.

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <regex>
#include <string>

#include "cli_support.h"

namespace {

const std::string kChart = SPECTRALIZE_SOURCE_DIR "/testimages/colorchecker_srgb16.png";
const std::string kHdri = SPECTRALIZE_SOURCE_DIR "/testimages/hdri_forest_256x128.exr";
const std::string kReflectance = RT_TABLES "/srgb_reflectance.spztab";
const std::string kEmission = RT_TABLES "/srgb_emission.spztab";

std::string quote(const std::string& s) {
  return "'" + s + "'";
}

// Runs `spectralize_path_tracer ARGS`; stdout and stderr captured.
e2e::Run run_tracer(const std::string& args, const e2e::Scratch& dir) {
  const std::string out = dir / "tracer.out", err = dir / "tracer.err";
  const std::string cmd = SPECTRALIZE_PATH_TRACER_BINARY " " + args + " >" + out + " 2>" + err;
  const int status = std::system(cmd.c_str());
  e2e::Run r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = e2e::slurp(out);
  r.err = e2e::slurp(err);
  return r;
}

// A number as the documents print it: 3 significant digits.
std::string g3(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

nlohmann::json read_json(const std::string& path) {
  return nlohmann::json::parse(e2e::slurp(path));
}

TEST(PathTracer, RtConvergesToTheDenseRenderOfSpectralizesOwnSpectra) {
  e2e::Scratch dir("path_tracer");
  // The dense reference's spectra: spectralize's own files for the two images (float samples).
  const std::string chart_exr = dir / "chart.exr", hdri_exr = dir / "hdri.exr";
  ASSERT_EQ(e2e::run(quote(kChart) +
                     " --colorspace 'sRGB - Texture' --mode reflectance -d float "
                     "-q -o " +
                     chart_exr)
                .exit_code,
            0);
  ASSERT_EQ(e2e::run(quote(kHdri) +
                     " --colorspace 'Linear Rec.709 (sRGB)' --mode emission "
                     "-d float -q -o " +
                     hdri_exr)
                .exit_code,
            0);
  const std::string json = dir / "convergence.json";
  const e2e::Run r =
      run_tracer("convergence --texture " + quote(kChart) + " --environment " + quote(kHdri) +
                     " --reflectance-table " + kReflectance + " --emission-table " + kEmission +
                     " --texture-spectra " + chart_exr + " --environment-spectra " + hdri_exr +
                     " --size 64 --spp 16,64 --json " + json,
                 dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json doc = read_json(json);
  ASSERT_EQ(doc.at("convergence").size(), 2u);
  const double at16 = doc["convergence"][0]["rt_vs_reference"]["mean"];
  const double at64 = doc["convergence"][1]["rt_vs_reference"]["mean"];
  ::testing::Test::RecordProperty("mean_dE2000_16spp", std::to_string(at16));
  ::testing::Test::RecordProperty("mean_dE2000_64spp", std::to_string(at64));
  // The wavelength noise of 4 hero wavelengths per path: below 2 dE2000 on average at 64 spp
  // (1.5 measured), and 4x the samples halve it (1/sqrt(spp): 2; 1.88 measured) within the
  // noise of 4096 pixels' means and the bias of dE at large errors.
  EXPECT_LT(at64, 2.0) << r.out;
  EXPECT_GT(at16 / at64, 1.6) << r.out;
  EXPECT_LT(at16 / at64, 2.4) << r.out;
  // The floor: rt's spectra over all 471 wavelengths against the files' on the same paths. Both
  // are the spectra of the same table (docs/DESIGN.md §14); what remains is float rounding.
  const double floor_mean = doc["floor"]["mean"], floor_max = doc["floor"]["max"];
  const double floor_xyz = doc["floor_relative_xyz"];
  ::testing::Test::RecordProperty("floor_max_dE2000", std::to_string(floor_max));
  EXPECT_LT(floor_mean, 0.01) << r.out;
  EXPECT_LT(floor_max, 0.05) << r.out;
  EXPECT_LT(floor_xyz, 1e-3) << r.out;
  // Every texel of the chart and the HDRI is inside the tables' gamuts.
  EXPECT_EQ(doc.at("mapped_lookups").get<long>(), 0);
  EXPECT_EQ(doc.at("invalid_lookups").get<long>(), 0);

  // The spectral files swapped: refused, the file named (a light's spectra are no texture).
  const e2e::Run swapped = run_tracer(
      "convergence --texture " + quote(kChart) + " --environment " + quote(kHdri) +
          " --reflectance-table " + kReflectance + " --emission-table " + kEmission +
          " --texture-spectra " + hdri_exr + " --environment-spectra " + chart_exr + " --size 4",
      dir);
  EXPECT_EQ(swapped.exit_code, 1);
  EXPECT_NE(swapped.err.find(hdri_exr), std::string::npos) << swapped.err;
}

TEST(PathTracer, ComparisonUnderIlluminantAGivesPlausibleNumbers) {
  e2e::Scratch dir("path_tracer_compare");
  for (const std::string light : {"A", "D65"}) {
    SCOPED_TRACE(light);
    const std::string json = dir / ("compare_" + light + ".json");
    const e2e::Run r =
        run_tracer("compare --texture " + quote(kChart) + " --environment " + quote(kHdri) +
                       " --reflectance-table " + kReflectance + " --illuminant " + light +
                       " --sigmoid-resolution 32 --size 48 --spp 16 --png-prefix " + (dir / light) +
                       " --json " + json,
                   dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const nlohmann::json doc = read_json(json);
    for (const char* key : {"rt_vs_truth", "baseline_vs_truth", "rt_vs_baseline"}) {
      const double mean = doc[key]["mean"], p95 = doc[key]["p95"], max = doc[key]["max"];
      ::testing::Test::RecordProperty(light + "_" + key + "_mean", std::to_string(mean));
      ::testing::Test::RecordProperty(light + "_" + key + "_p95", std::to_string(p95));
      // Sanity only: uplifted colours are near their measured ones, not equal (metamerism).
      EXPECT_GT(mean, 0.0) << key;
      EXPECT_LE(mean, p95) << key;
      EXPECT_LE(p95, max) << key;
      EXPECT_LT(p95, 10.0) << key;
      EXPECT_GT(doc[key]["pixels"].get<int>(), 48 * 48 / 4) << key;  // 46% of the frame
    }
    // The figures: three renders and two difference maps, at their sizes.
    for (const char* name : {"_truth", "_rt", "_baseline", "_rt_dE", "_baseline_dE"}) {
      auto in = OIIO::ImageInput::open(dir / (light + name + ".png"));
      ASSERT_TRUE(in) << name;
      EXPECT_EQ(in->spec().width, 48);
      EXPECT_EQ(in->spec().height, std::string(name).find("dE") != std::string::npos ? 128 : 48);
    }
  }
}

TEST(PathTracer, BadCommandLinesAndFiles) {
  e2e::Scratch dir("path_tracer_bad");
  EXPECT_EQ(run_tracer("paint", dir).exit_code, 2);
  EXPECT_EQ(run_tracer("compare --texture " + quote(kChart), dir).exit_code, 2);
  const e2e::Run spp = run_tracer("compare --spp 16,4", dir);
  EXPECT_EQ(spp.exit_code, 2);
  EXPECT_NE(spp.err.find("--spp"), std::string::npos) << spp.err;
  const e2e::Run help = run_tracer("--help", dir);
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_NE(help.out.find("convergence"), std::string::npos);
  // A missing table and a table of the other mode: exit 1, the file named.
  const std::string missing = dir / "none.spztab";
  const e2e::Run gone = run_tracer("compare --texture " + quote(kChart) + " --environment " +
                                       quote(kHdri) + " --reflectance-table " + missing,
                                   dir);
  EXPECT_EQ(gone.exit_code, 1);
  EXPECT_NE(gone.err.find(missing), std::string::npos) << gone.err;
  const e2e::Run mode = run_tracer("compare --texture " + quote(kChart) + " --environment " +
                                       quote(kHdri) + " --reflectance-table " + kEmission,
                                   dir);
  EXPECT_EQ(mode.exit_code, 1);
  EXPECT_NE(mode.err.find(kEmission), std::string::npos) << mode.err;
  EXPECT_NE(mode.err.find("emission"), std::string::npos) << mode.err;
  // The comparison's truth is the ColorChecker chart's layout: another texture is refused.
  const e2e::Run chart = run_tracer("compare --texture " + quote(kHdri) + " --texture-space " +
                                        "'Linear Rec.709 (sRGB)' --environment " + quote(kHdri) +
                                        " --reflectance-table " + kReflectance + " --size 4",
                                    dir);
  EXPECT_EQ(chart.exit_code, 1);
  EXPECT_NE(chart.err.find(kHdri), std::string::npos) << chart.err;
  EXPECT_NE(chart.err.find("110 x 74"), std::string::npos) << chart.err;
}

// The documents' figures (docs/figures/render_*.png) are what `make docs-renders` makes from the
// current code, byte for byte; and the numbers docs/RENDERERS.md quotes are that run's.
TEST(PathTracerSlow, DocumentFiguresAreReproducedByteForByte) {
#ifdef SPECTRALIZE_SANITIZED
  GTEST_SKIP() << "the figures are made by the release build";
#endif
  e2e::Scratch dir("path_tracer_docs");
  const std::string cmd = "bash " SPECTRALIZE_SOURCE_DIR "/cmake/renders.sh " SPECTRALIZE_BUILD_DIR
                          " " +
                          (dir / "renders") + " >" + (dir / "log") + " 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << e2e::slurp(dir / "log");
  int compared = 0;
  for (const auto& e :
       std::filesystem::directory_iterator(SPECTRALIZE_SOURCE_DIR "/docs/figures")) {
    const std::string name = e.path().filename().string();
    if (name.rfind("render_", 0) != 0) continue;
    ++compared;
    EXPECT_EQ(e2e::slurp(dir / ("renders/" + name)), e2e::slurp(e.path().string()))
        << name << ": run make docs-renders and commit docs/figures";
  }
  EXPECT_EQ(compared, 5);
  // The numbers docs/RENDERERS.md quotes are this run's (3 significant digits).
  const std::string doc = e2e::slurp(SPECTRALIZE_SOURCE_DIR "/docs/RENDERERS.md");
  const nlohmann::json conv = read_json(dir / "renders/convergence.json");
  for (const auto& p : conv.at("convergence")) {
    const auto& st = p.at("rt_vs_reference");
    const std::string row = "| " + std::to_string(p.at("spp").get<int>()) + " | " +
                            g3(st.at("mean")) + " | " + g3(st.at("p95")) + " | " +
                            g3(st.at("max")) + " |";
    EXPECT_NE(doc.find(row), std::string::npos) << "RENDERERS.md lacks the row " << row;
  }
  const auto& fl = conv.at("floor");
  const std::string floor_row = "| all 471 wavelengths | " + g3(fl.at("mean")) + " | " +
                                g3(fl.at("p95")) + " | " + g3(fl.at("max")) + " |";
  EXPECT_NE(doc.find(floor_row), std::string::npos) << "RENDERERS.md lacks " << floor_row;
  for (const std::string light : {"A", "D65"}) {
    const nlohmann::json c = read_json(dir / ("renders/compare_" + light + ".json"));
    const std::string row = "| " + light + " | " + g3(c["rt_vs_truth"]["mean"]) + " | " +
                            g3(c["rt_vs_truth"]["p95"]) + " | " +
                            g3(c["baseline_vs_truth"]["mean"]) + " | " +
                            g3(c["baseline_vs_truth"]["p95"]) + " |";
    EXPECT_NE(doc.find(row), std::string::npos) << "RENDERERS.md lacks the row " << row;
  }
}

}  // namespace
