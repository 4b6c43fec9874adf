// End-to-end tests of `spectralize_figures`: `figures` writes the paper's figures at their
// stated sizes, the halves of the D65 spheres are indistinguishable (printed max dE2000 <= 0.01,
// and the written pixels agree with their mirror pixels) while under A and F11 they are not;
// `validate` writes the tables of the ColorChecker (24) and AMPAS (190) sets per configuration,
// exact under D65, and the natural model's metamerism stays ahead of rgb2spec.

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <string>
#include <vector>

#include "cli_support.h"
#include "exr_support.h"

namespace {

// Runs `spectralize_figures ARGS`; stdout and stderr captured.
e2e::Run run_figures(const std::string& args, const e2e::Scratch& dir) {
  const std::string out = dir / "stdout.txt", err = dir / "stderr.txt";
  const std::string cmd = std::string(SPECTRALIZE_TOOL_ENV) + " " SPECTRALIZE_FIGURES_BINARY " " +
                          args + " >" + out + " 2>" + err;
  const int status = std::system(cmd.c_str());
  e2e::Run r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = e2e::slurp(out);
  r.err = e2e::slurp(err);
  return r;
}

// Largest 8-bit difference between a pixel of the left half and its mirror pixel, over the
// sphere's rows (the labels at the top are skipped).
double max_mirror_difference(const e2e::Exr& img) {
  double worst = 0;
  for (int y = img.height / 8; y < img.height; ++y)
    for (int x = 0; x < img.width / 2; ++x)
      for (int c = 0; c < 3; ++c) {
        const auto at = [&](int px) { return img.at(px, y, c); };
        worst = std::max(worst, 255.0 * std::abs(at(x) - at(img.width - 1 - x)));
      }
  return worst;
}

TEST(Figures, WritesThePapersFiguresAndMeasuresTheSphereHalves) {
  e2e::Scratch dir("figures");
  const std::string out = dir / "figures";
  const e2e::Run r = run_figures("figures " + out, dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;

  // Every figure exists, at its stated size.
  const std::map<std::string, std::pair<int, int>> sizes = {
      {"fig1_light_spectrum.png", {1000, 600}},     {"fig3_surface_spectrum.png", {1000, 600}},
      {"fig2_sphere_light.png", {512, 512}},        {"fig4_sphere_surface.png", {512, 512}},
      {"fig5_sphere_surface_A.png", {512, 512}},    {"fig6_sphere_surface_F11.png", {512, 512}},
      {"fig2_sphere_light_dE.png", {512, 592}},     {"fig4_sphere_surface_dE.png", {512, 592}},
      {"fig5_sphere_surface_A_dE.png", {512, 592}}, {"fig6_sphere_surface_F11_dE.png", {512, 592}}};
  for (const auto& [file, size] : sizes) {
    const e2e::Exr img = e2e::read_exr(out + "/" + file);  // any image OIIO reads
    EXPECT_EQ(img.width, size.first) << file;
    EXPECT_EQ(img.height, size.second) << file;
    EXPECT_GE(img.channels.size(), 3u) << file;
  }
  // Nothing but the figures (no temporary files left).
  std::size_t files = 0;
  for (const auto& e : std::filesystem::directory_iterator(out)) {
    ++files;
    EXPECT_EQ(e.path().filename().string()[0] == '.', false) << e.path();
  }
  EXPECT_EQ(files, sizes.size());

  // The printed differences: "NAME: max dE2000 VALUE ...", one line per sphere.
  std::map<std::string, double> de;
  const std::regex line(R"((fig\w+): max dE2000 ([0-9.eE+-]+))");
  for (std::sregex_iterator it(r.out.begin(), r.out.end(), line), end; it != end; ++it)
    de[(*it)[1]] = std::stod((*it)[2]);
  ASSERT_EQ(de.size(), 4u) << r.out;
  // The paper's claim: the halves are indistinguishable under the light they were made for.
  EXPECT_LE(de.at("fig2_sphere_light"), 0.01) << r.out;
  EXPECT_LE(de.at("fig4_sphere_surface"), 0.01) << r.out;
  // Under other lights an RGB renderer and a spectral one legitimately disagree.
  EXPECT_GT(de.at("fig5_sphere_surface_A"), 0.5) << r.out;
  EXPECT_GT(de.at("fig6_sphere_surface_F11"), 0.5) << r.out;

  // The written pixels say the same: mirror pixels equal (to 8-bit rounding) under D65.
  EXPECT_LE(max_mirror_difference(e2e::read_exr(out + "/fig2_sphere_light.png")), 1.0);
  EXPECT_LE(max_mirror_difference(e2e::read_exr(out + "/fig4_sphere_surface.png")), 1.0);
  EXPECT_GT(max_mirror_difference(e2e::read_exr(out + "/fig5_sphere_surface_A.png")), 10.0);
  EXPECT_GT(max_mirror_difference(e2e::read_exr(out + "/fig6_sphere_surface_F11.png")), 5.0);
}

// The largest difference of two images' samples (in 8-bit steps for 8-bit files), or +inf when
// their sizes or channels differ or one does not read.
double max_sample_difference(const std::string& a, const std::string& b) {
  const e2e::Exr x = e2e::read_exr(a), y = e2e::read_exr(b);
  if (x.width == 0 || x.width != y.width || x.height != y.height || x.channels != y.channels)
    return std::numeric_limits<double>::infinity();
  double worst = 0;
  for (std::size_t i = 0; i < x.pixels.size(); ++i)
    worst = std::max(worst, std::abs(static_cast<double>(x.pixels[i]) - y.pixels[i]) * 255.0);
  return worst;
}

// Truth (the guide): the figures shown in the guide are what `make docs-figures` makes from the
// current code: the same pixels, and making them twice gives the same bytes. (Pixels, not
// bytes, against the committed copies: each OpenImageIO writes its own PNG container, e.g. 3.x
// adds an eXIf chunk and orders the colour chunks otherwise.)
TEST(Figures, ReadmeCopiesAreReproducedPixelForPixel) {
#ifdef SPECTRALIZE_SANITIZED
  // The copies are made by the release build; -O1 rounds differently in the last bits.
  GTEST_SKIP() << "the copies are checked by the release build";
#endif
  e2e::Scratch a("figs_a"), b("figs_b");
  ASSERT_EQ(run_figures("figures " + a.dir.string(), a).exit_code, 0);
  ASSERT_EQ(run_figures("figures " + b.dir.string(), b).exit_code, 0);
  const std::string docs = SPECTRALIZE_SOURCE_DIR "/docs/figures/";
  for (const auto& entry : std::filesystem::directory_iterator(docs)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("render_", 0) == 0) continue;   // the path tracer's (path_tracer_test.cpp)
    if (name.rfind("mitsuba_", 0) == 0) continue;  // Mitsuba's (tests/mitsuba, docs-mitsuba)
    SCOPED_TRACE(name);
    EXPECT_EQ(e2e::slurp(a / name), e2e::slurp(b / name));
    std::string made = a / name;
    if (name.rfind("fig1", 0) != 0 && name.rfind("fig3", 0) != 0) {  // spheres: at 256 px
      made = a / ("small_" + name);
      ASSERT_EQ(
          std::system(
              ("oiiotool --nosoftwareattrib " + (a / name) + " --resize 256x0 -o " + made).c_str()),
          0);
    }
    EXPECT_EQ(max_sample_difference(made, entry.path().string()), 0.0)
        << "run make docs-figures and commit docs/figures";
  }
}

TEST(Figures, WrongCommandLineExitsTwo) {
  e2e::Scratch dir("figures_usage");
  EXPECT_EQ(run_figures("paint " + dir / "x", dir).exit_code, 2);
  EXPECT_EQ(run_figures("figures", dir).exit_code, 2);
  const e2e::Run help = run_figures("--help", dir);
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_NE(help.out.find("validate OUTDIR"), std::string::npos);
  // An output folder that cannot be made (a file is in the way): exit 1, the path named.
  const std::string blocker = dir.write("file", "x");
  const e2e::Run bad = run_figures("figures " + blocker + "/sub", dir);
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_NE(bad.err.find(blocker), std::string::npos) << bad.err;
}

const std::vector<std::string> kLights = {"A", "FL11", "FL2", "LED-B3", "HP1", "D50"};

// The tables: every row on both sets in both spaces, exact rows exact under D65, bounded, six
// lights per patch, the reference lines present and honest.
void check_tables(const nlohmann::json& doc, const std::string& md, const e2e::Run& r) {
  const std::vector<std::string>& lights = kLights;
  EXPECT_NE(md.find("## Reflectances: summary"), std::string::npos);
  // Six lights besides D65, in the order the tables use.
  EXPECT_EQ(doc.at("lights").get<std::vector<std::string>>(), lights);

  const auto& configs = doc.at("configurations");
  ASSERT_GE(configs.size(), 18u);  // 6 model rows and 3 reference lines, x 2 spaces
  bool smooth = false, natural = false, fixed_filters = false, neighbour = false, fit = false;
  for (const auto& c : configs) {
    const std::string name = c.at("name");
    SCOPED_TRACE(name + " / " + c.at("space").get<std::string>());
    ASSERT_TRUE(c.at("available").get<bool>()) << c.value("error", "");
    const bool model = !c.at("model").get<std::string>().empty();
    const bool exact = c.at("exact").get<bool>();
    smooth = smooth || c.at("model") == "smooth";
    natural = natural || c.at("model") == "natural";
    fixed_filters = fixed_filters || c.at("filter") == "0.9";
    const bool nn = name.find("nearest neighbour") != std::string::npos;
    neighbour = neighbour || nn;
    fit = fit || name.find("rgb2spec, fitted") != std::string::npos;
    EXPECT_TRUE(exact || !model) << "every registered model is exact";
    EXPECT_NE(md.find(name), std::string::npos);
    ASSERT_EQ(c.at("sets").size(), 2u);
    EXPECT_EQ(c.at("sets")[0].at("patches").size(), 24u);   // ColorChecker
    EXPECT_EQ(c.at("sets")[1].at("patches").size(), 190u);  // AMPAS 190
    for (const auto& set : c.at("sets")) {
      double worst_a = 0;
      for (const auto& p : set.at("patches")) {
        SCOPED_TRACE(p.at("name").get<std::string>());
        // rgb2spec comes within its fit's tolerance (the table: its interpolation) of the colour.
        EXPECT_LE(p.at("delta_e_d65").get<double>(), exact ? 0.01 : 0.5);
        if (exact) {
          EXPECT_LE(p.at("relative_xyz_error").get<double>(), 1e-5);
          // Patches inside the space come back to their measured colour under D65 too.
          if (!p.at("clipped").get<bool>()) {
            EXPECT_LE(p.at("delta_e_d65_measured").get<double>(), 0.01);
          }
        }
        EXPECT_GE(p.at("rho_min").get<double>(), 0.0);
        EXPECT_LE(p.at("rho_max").get<double>(), 1.0 + 1e-12);
        ASSERT_EQ(p.at("delta_e").size(), lights.size());
        for (const std::string& l : lights) {
          EXPECT_GE(p.at("delta_e").at(l).get<double>(), 0.0);
        }
        worst_a = std::max(worst_a, p.at("delta_e").at("A").get<double>());
        // Leave one out: no patch is predicted from its own measurement (which would give it
        // back, RMSE 0), and the prediction is another measured shape, not the measurement.
        if (nn) {
          EXPECT_GT(p.at("rmse").get<double>(), 1e-4);
        }
      }
      // Metamerism is real: some reconstruction differs from its measurement under A.
      EXPECT_GT(worst_a, 0.1);
      const auto& summary = set.at("summary");
      if (exact) {
        EXPECT_LE(summary.at("delta_e_d65").at("max").get<double>(), 0.01);
      }
      for (const std::string& l : lights) {
        const auto& d = summary.at("delta_e").at(l);
        EXPECT_LE(d.at("median").get<double>(), d.at("p95").get<double>()) << l;
        EXPECT_LE(d.at("p95").get<double>(), d.at("max").get<double>()) << l;
      }
    }
    // Lights are made by the models; a reference line makes none.
    ASSERT_EQ(c.at("lights").size(), model ? 3u : 0u);
    for (const auto& l : c.at("lights")) {
      EXPECT_LE(l.at("relative_xyz_error").get<double>(), 1e-5);
      EXPECT_LE(l.at("delta_e_light").get<double>(), 0.01);  // a light's own colour is exact
      EXPECT_GE(l.at("checker_delta_e_max").get<double>(),
                l.at("checker_delta_e_median").get<double>());
    }
  }
  EXPECT_TRUE(smooth) << "the smooth model is a row of the table";
  EXPECT_TRUE(natural) << "the natural model is a row of the table";
  EXPECT_TRUE(neighbour) << "the nearest-neighbour reference is a row of the table";
  EXPECT_TRUE(fit) << "rgb2spec is a row of the table";
  // The RGB renderer's baseline, per space and set, on the same patches, under every light.
  ASSERT_EQ(doc.at("rgb_renderer").size(), 4u);
  for (const auto& b : doc.at("rgb_renderer")) {
    EXPECT_EQ(b.at("patches").size(), b.at("set") == "ColorChecker" ? 24u : 190u);
    for (const std::string& l : lights) {
      EXPECT_GT(b.at("delta_e").at(l).at("max").get<double>(), 0.1) << l;
    }
  }
  EXPECT_TRUE(fixed_filters);
  // The stdout summary is the Markdown table.
  EXPECT_NE(r.out.find("| set | configuration | space |"), std::string::npos);
}

// One row's summary of one set: {"delta_e": {light: {median, p95, max}}, ...}; the row of the
// registered model `name_part`, else the first whose name contains it.
// Views, not strings: a temporary string argument would make the returned reference (into
// `doc`) look dangling to GCC 13+'s -Wdangling-reference.
const nlohmann::json& summary_of(const nlohmann::json& doc, std::string_view name_view,
                                 std::string_view space_view, std::string_view set_view) {
  const std::string name_part(name_view), space(space_view), set(set_view);
  const auto& rows = doc.at("configurations");
  const bool model = std::any_of(rows.begin(), rows.end(),
                                 [&](const auto& c) { return c.at("model") == name_part; });
  for (const auto& c : rows)
    if ((model ? c.at("model") == name_part
               : c.at("name").get<std::string>().find(name_part) != std::string::npos) &&
        c.at("space") == space)
      for (const auto& s : c.at("sets"))
        if (s.at("name") == set) return s.at("summary");
  throw std::runtime_error("no row " + name_part + " / " + space + " / " + set);
}

// The natural and exemplar models against rgb2spec (Jakob & Hanika 2019, the project's baseline
// fitted per colour) on both development sets in both spaces: ahead in every median under all
// six lights, and in every p95 under A, FL11 and LED-B3 (under HP1 and FL2 rgb2spec's p95 is
// lower than natural's on the ColorChecker, docs/MODEL_STUDY.md). The exemplar model (its row
// cross-validated) no worse than natural in any median by more than 0.05 (the rule that made it
// the default). The baseline itself within 0.03 of the numbers measured outside this project
// with the same protocol (Linear Rec.2020, so no patch is clipped: A and FL11 median / p95),
// pbrt-v4's 64^3 table within 0.05 of the direct fit, and both models within 0.05 of the values
// measured when the exemplar model was made the default (a regression would move them).
void check_models_against_rgb2spec(const nlohmann::json& doc) {
  struct Expect {
    const char* set;
    double rgb2spec[4];  // A median, A p95, FL11 median, FL11 p95 (Rec.2020)
    double natural[4];   // as measured
    double exemplar[4];
  };
  const Expect expected[] = {
      {"ColorChecker",
       {1.15, 2.79, 1.17, 2.86},
       {0.838, 2.46, 0.675, 2.23},
       {0.303, 1.41, 0.377, 1.18}},
      {"AMPAS 190", {1.23, 3.62, 1.67, 4.28}, {1.13, 3.08, 1.12, 2.99}, {0.959, 3.08, 1.07, 2.94}},
  };
  for (const char* model : {"natural", "exemplar"}) {
    int ahead = 0, numbers = 0;
    for (const std::string space : {"Linear Rec.709 (sRGB)", "Linear Rec.2020"})
      for (const Expect& e : expected) {
        SCOPED_TRACE(std::string(model) + " / " + space + " / " + e.set);
        const auto& sum = summary_of(doc, model, space, e.set);
        const auto& n = sum.at("delta_e");
        const auto& nat = summary_of(doc, "natural", space, e.set).at("delta_e");
        const auto& fit = summary_of(doc, "rgb2spec, fitted", space, e.set).at("delta_e");
        const auto& table = summary_of(doc, "rgb2spec, 64", space, e.set).at("delta_e");
        for (const std::string& l : kLights) {
          SCOPED_TRACE(l);
          const double n50 = n[l]["median"], n95 = n[l]["p95"], nmax = n[l]["max"];
          const double f50 = fit[l]["median"], f95 = fit[l]["p95"], fmax = fit[l]["max"];
          EXPECT_LT(n50, f50);
          if (l == "A" || l == "FL11" || l == "LED-B3") {
            EXPECT_LT(n95, f95);
          }
          EXPECT_LE(n50, nat[l]["median"].get<double>() + 0.05);
          EXPECT_NEAR(table[l]["median"].get<double>(), f50, 0.05);
          ahead += (n50 < f50) + (n95 < f95) + (nmax < fmax);
          numbers += 3;
        }
        if (space != "Linear Rec.2020") continue;
        EXPECT_EQ(sum.at("clipped_patches").get<int>(), 0);
        const double got[4] = {n["A"]["median"], n["A"]["p95"], n["FL11"]["median"],
                               n["FL11"]["p95"]};
        const double base[4] = {fit["A"]["median"], fit["A"]["p95"], fit["FL11"]["median"],
                                fit["FL11"]["p95"]};
        const double* want = std::string(model) == "natural" ? e.natural : e.exemplar;
        for (int k = 0; k < 4; ++k) {
          EXPECT_NEAR(base[k], e.rgb2spec[k], 0.03) << "statistic " << k;
          EXPECT_NEAR(got[k], want[k], 0.05) << "statistic " << k;
        }
      }
    std::printf("  %s ahead of rgb2spec on %d of %d numbers (median, p95, max)\n", model, ahead,
                numbers);
  }
}

// The render-time table (docs/DESIGN.md §14: what images, --color and a renderer's table file
// give) behaves like the model whose node spectra it blends: the natural model's table within
// 0.05 of the solved natural model in median and p95 under A and FL11, on both sets in both
// spaces.
void check_table_against_model(const nlohmann::json& doc) {
  for (const std::string space : {"Linear Rec.709 (sRGB)", "Linear Rec.2020"})
    for (const char* set : {"ColorChecker", "AMPAS 190"}) {
      SCOPED_TRACE(space + " / " + set);
      const auto& table = summary_of(doc, "natural, render-time table", space, set).at("delta_e");
      const auto& solved = summary_of(doc, "natural", space, set).at("delta_e");
      for (const char* light : {"A", "FL11"})
        for (const char* stat : {"median", "p95"}) {
          EXPECT_NEAR(table[light][stat].get<double>(), solved[light][stat].get<double>(), 0.05)
              << light << " " << stat;
        }
    }
}

// One run of `validate` for both checks (it builds two 64^3 rgb2spec tables: CI time).
TEST(Validation, TablesAreExactAndTheModelsLeadRgb2spec) {
  e2e::Scratch dir("validation");
  const std::string out = dir / "validation";
  const e2e::Run r = run_figures("validate " + out, dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json doc = nlohmann::json::parse(e2e::slurp(out + "/validation.json"));
  check_tables(doc, e2e::slurp(out + "/validation.md"), r);
  check_models_against_rgb2spec(doc);
  check_table_against_model(doc);
}

}  // namespace
