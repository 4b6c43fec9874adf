// End-to-end tests of `spectralize --color` through the real binary: what a user sees.

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cli_support.h"

using e2e::run;
using Json = nlohmann::json;

namespace {

// Linear Rec.709 (D65) -> XYZ from the primaries (IEC 61966-2-1), written out independently.
constexpr double kRec709[3][3] = {{0.41239079926595948, 0.35758433938387796, 0.18048078840183429},
                                  {0.21263900587151036, 0.71516867876775593, 0.07219231536073372},
                                  {0.01933081871559185, 0.11919477979462599, 0.95053215224966058}};

std::array<double, 3> rec709(double r, double g, double b) {
  std::array<double, 3> out;
  for (int i = 0; i < 3; ++i) out[i] = kRec709[i][0] * r + kRec709[i][1] * g + kRec709[i][2] * b;
  return out;
}

struct Csv {
  std::vector<std::string> header;
  std::vector<double> nm;
  std::vector<std::vector<double>> values;  // per column after wavelength
};

Csv parse_csv(const std::string& text) {
  Csv c;
  std::stringstream ss(text);
  std::string line;
  std::getline(ss, line);
  std::stringstream hs(line);
  for (std::string cell; std::getline(hs, cell, ',');) c.header.push_back(cell);
  c.values.resize(c.header.size() - 1);
  while (std::getline(ss, line)) {
    std::stringstream ls(line);
    std::string cell;
    std::getline(ls, cell, ',');
    c.nm.push_back(std::stod(cell));
    for (auto& col : c.values) {
      std::getline(ls, cell, ',');
      col.push_back(std::stod(cell));
    }
  }
  return c;
}

// Largest sample in [a, b] nm and mean over [c, d] nm.
double max_in(const std::vector<double>& nm, const std::vector<double>& v, double a, double b) {
  double m = 0;
  for (std::size_t i = 0; i < nm.size(); ++i)
    if (nm[i] >= a && nm[i] <= b) m = std::max(m, v[i]);
  return m;
}
double mean_in(const std::vector<double>& nm, const std::vector<double>& v, double a, double b) {
  double s = 0;
  int n = 0;
  for (std::size_t i = 0; i < nm.size(); ++i)
    if (nm[i] >= a && nm[i] <= b) s += v[i], ++n;
  return s / n;
}

TEST(CliColor, HelpGoesToStdoutAndExitsZero) {
  auto r = run("--help");
  EXPECT_EQ(r.exit_code, 0);
  for (const char* flag :
       {"--color", "--colorspace", "--mode", "--wavelengths", "--observer", "--illuminant",
        "--filter", "--model", "--emission-basis", "--format", "--config"})
    EXPECT_NE(r.out.find(flag), std::string::npos) << flag << " missing from --help";
}

// The paper's light by the paper's model: exact (OCIO's float conversion limits this to ~1e-7),
// non-negative, and the default edge filter leaves no end sample above the mean over 400-700 nm.
TEST(CliColor, PaperLightIsExactNonNegativeAndFreeOfEdgePeaks) {
  auto r = run("--color 6000,5000,1000 --model paper");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  Csv c = parse_csv(r.out);
  ASSERT_EQ(c.header, (std::vector<std::string>{"wavelength_nm", "value"}));
  ASSERT_EQ(c.nm.size(), 81u);
  EXPECT_EQ(c.nm.front(), 380);
  EXPECT_EQ(c.nm.back(), 780);
  for (double v : c.values[0]) {
    EXPECT_GE(v, 0);
  }
  auto xyz = rec709(6000, 5000, 1000);
  auto got = e2e::integrate(c.nm, c.values[0], "cie1931_2deg_cmf_1nm.csv");
  EXPECT_LE(e2e::rel_err(got, xyz[0], xyz[1], xyz[2]), 1e-5);
  double mean = mean_in(c.nm, c.values[0], 400, 700);
  EXPECT_LE(max_in(c.nm, c.values[0], 380, 400), mean);
  EXPECT_LE(max_in(c.nm, c.values[0], 760, 780), mean);
}

// The paper's surface under D65: a reflectance in [0, 1] whose reflected colour, relative to the
// reflected white, is the input (white balance W_ref / W_D65 per docs/DESIGN.md §3).
TEST(CliColor, PaperSurfaceIsAnExactBoundedReflectance) {
  auto r = run("--color 0.21,0.72,0.15 --mode reflectance --format json --model paper");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  Json j = Json::parse(r.out);
  EXPECT_EQ(j["status"], "ok");
  EXPECT_EQ(j["mode"], "reflectance");
  EXPECT_EQ(j["illuminant"], "D65");
  std::vector<double> nm = j["wavelengths_nm"], v = j["values"];
  ASSERT_EQ(nm.size(), 81u);
  for (double x : v) {
    EXPECT_GE(x, 0);
    EXPECT_LE(x, 1 + 1e-12);
  }
  auto white = e2e::integrate(nm, std::vector<double>(nm.size(), 1.0), "cie1931_2deg_cmf_1nm.csv",
                              "cie_illuminant_d65_1nm.csv");
  auto xyz = rec709(0.21, 0.72, 0.15);
  const double d65[3] = {0.3127 / 0.3290, 1.0, 0.3583 / 0.3290};
  auto got = e2e::integrate(nm, v, "cie1931_2deg_cmf_1nm.csv", "cie_illuminant_d65_1nm.csv");
  EXPECT_NEAR(white.Y, 1.0, 1e-12);
  EXPECT_LE(e2e::rel_err(got, xyz[0] * white.X / d65[0], xyz[1] * white.Y / d65[1],
                         xyz[2] * white.Z / d65[2]),
            1e-5);
  // The table's spectrum is float (as files store it): exact to float precision.
  EXPECT_EQ(j["method"], "table");
  EXPECT_LE(j["relative_error"].get<double>(), 1e-6);
  // Solved directly, every field of the result is in the JSON, to double precision.
  r = run("--color 0.21,0.72,0.15 --mode reflectance --format json --model paper --method exact");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  j = Json::parse(r.out);
  for (const char* key : {"input_rgb", "colorspace", "wavelengths", "observer", "filter", "method",
                          "input_xyz", "target_xyz", "xyz", "relative_error", "admissible",
                          "dropped", "bounded", "edge_capped", "gamut_distance"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_LE(j["relative_error"].get<double>(), 1e-9);
  EXPECT_GT(j["admissible"].get<long>(), 0);
}

TEST(CliColor, WhiteReflectanceIsOneEverywhere) {
  for (const char* il : {"D65", "A", "D50"}) {
    auto r = run(std::string("--color 1,1,1 --mode reflectance --format json --illuminant ") + il);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    Json j = Json::parse(r.out);
    // OCIO converts in float: white arrives as D65 to ~1e-7, so rho is 1 to that precision.
    for (double x : j["values"]) {
      EXPECT_NEAR(x, 1.0, 1e-5) << il;
    }
  }
}

TEST(CliColor, ColourSpacesAndAliasesGoThroughOcio) {
  // sRGB-encoded 0.5 decodes to 0.214041 linear; grey keeps Y equal to that.
  auto r = run("--color 0.5,0.5,0.5 --colorspace srgb_tx --format json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  Json j = Json::parse(r.out);
  EXPECT_EQ(j["colorspace"], "sRGB - Texture");
  EXPECT_NEAR(j["input_xyz"][1].get<double>(), 0.2140411, 1e-6);
  // ACEScg white is D65 white after the Bradford adaptation in the shipped config.
  r = run("--color 1,1,1 --colorspace acescg --format json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  j = Json::parse(r.out);
  EXPECT_EQ(j["colorspace"], "ACEScg");
  EXPECT_NEAR(j["input_xyz"][0].get<double>(), 0.3127 / 0.3290, 1e-5);
  EXPECT_NEAR(j["input_xyz"][2].get<double>(), 0.3583 / 0.3290, 1e-5);
  for (const char* cs : {"\"Linear Rec.2020\"", "lin_p3d65", "ACES2065-1", "ACEScct", "CIE-XYZ-D65",
                         "Raw", "lin_srgb", "lin_rec2020"}) {
    r = run(std::string("--color 0.3,0.4,0.2 --colorspace ") + cs);
    EXPECT_EQ(r.exit_code, 0) << cs << ": " << r.err;
    // A data space's values are not a colour: said, as for an image, only for Raw.
    EXPECT_EQ(r.err.find("marked as data") != std::string::npos, std::string(cs) == "Raw")
        << cs << ": " << r.err;
  }
}

TEST(CliColor, SeveralColoursGiveOneColumnEach) {
  auto r = run("--color 1,0,0 --color 0,1,0 --color 0,0,1");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  Csv c = parse_csv(r.out);
  EXPECT_EQ(c.header, (std::vector<std::string>{"wavelength_nm", "value_1", "value_2", "value_3"}));
  auto green = rec709(0, 1, 0);
  auto got = e2e::integrate(c.nm, c.values[1], "cie1931_2deg_cmf_1nm.csv");
  EXPECT_LE(e2e::rel_err(got, green[0], green[1], green[2]), 1e-5);
}

TEST(CliColor, OtherGridsAndTheTenDegreeObserverStayExact) {
  auto r = run("--color 0.2,0.5,0.8 --observer cie1964 --wavelengths 400:700:10");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  Csv c = parse_csv(r.out);
  ASSERT_EQ(c.nm.size(), 31u);
  auto xyz = rec709(0.2, 0.5, 0.8);
  // Target is the input XYZ, integrated with the 10 degree CMFs (docs/DESIGN.md §3: same
  // integration).
  auto got = e2e::integrate(c.nm, c.values[0], "cie1964_10deg_cmf_1nm.csv");
  EXPECT_LE(e2e::rel_err(got, xyz[0], xyz[1], xyz[2]), 1e-5);
}

TEST(CliColor, OutOfGamutColoursAreMappedAndReported) {
  // ACES2065-1 green (AP0 primary at x, y = 0, 1) lies far outside the spectral locus.
  auto r = run("--color 0,1,0 --colorspace ACES2065-1 --format json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("out of gamut"), std::string::npos) << r.err;
  Json j = Json::parse(r.out);
  EXPECT_EQ(j["status"], "out_of_gamut");
  EXPECT_GT(j["gamut_distance"].get<double>(), 0.01);
  EXPECT_LE(j["relative_error"].get<double>(), 1e-6);  // the table's float spectrum
  // Luminance is kept by the mapping (toward white at constant Y).
  EXPECT_NEAR(j["target_xyz"][1].get<double>(), j["input_xyz"][1].get<double>(), 1e-9);
  // A bright reflectance (Y > 1) is dimmed and desaturated, never above 1.
  r = run("--color 2,2,2 --mode reflectance --format json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  j = Json::parse(r.out);
  EXPECT_EQ(j["status"], "out_of_gamut");
  for (double x : j["values"]) {
    EXPECT_LE(x, 1 + 1e-12);
  }
}

TEST(CliColor, NegativeLuminanceIsOutOfGamutAndMappedToBlackAsInImages) {
  // No light or surface has Y < 0: as a pixel of an image is (the guide's "Conventions"
  // (docs/guide/conventions.md)), the colour is out of gamut, mapped to black (the zero spectrum)
  // with a warning, and the job is done.
  auto r = run("--color 0.1,-0.2,0.1 --colorspace CIE-XYZ-D65 --format json");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("negative luminance"), std::string::npos) << r.err;
  Json j = Json::parse(r.out);
  EXPECT_EQ(j["status"], "out_of_gamut");
  for (double x : j["values"]) EXPECT_EQ(x, 0.0);
  // AP0's blue primary has negative luminance (y = -0.077), in either mode.
  for (const char* mode : {"emission", "reflectance"}) {
    r = run(std::string("--color 0,0,1 --colorspace ACES2065-1 --format json --mode ") + mode);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.err.find("negative luminance"), std::string::npos) << r.err;
    j = Json::parse(r.out);
    EXPECT_EQ(j["status"], "out_of_gamut") << mode;
    for (double x : j["values"]) EXPECT_EQ(x, 0.0) << mode;
  }
}

struct BadArgs {
  const char* args;
  const char* expected;  // a piece of the message
};

class CliColorBadArgs : public ::testing::TestWithParam<BadArgs> {};

TEST_P(CliColorBadArgs, ExitTwoWithAMessageNamingTheProblem) {
  auto r = run(GetParam().args);
  EXPECT_EQ(r.exit_code, 2) << GetParam().args << "\n" << r.err;
  EXPECT_NE(r.err.find("spectralize ERROR"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(GetParam().expected), std::string::npos)
      << "args: " << GetParam().args << "\nstderr: " << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
}

INSTANTIATE_TEST_SUITE_P(
    Cases, CliColorBadArgs,
    ::testing::Values(
        BadArgs{"--color 1,2,3 --colorspace NotASpace", "unknown colour space 'NotASpace'"},
        BadArgs{"--color 1,2,3 --colorspace NotASpace", "ACEScg"},  // lists the valid names
        BadArgs{"--color 1,2", "expected 3 components"},
        BadArgs{"--color 1,2,3,4", "expected 3 components"},
        BadArgs{"--color a,b,c", "'a' is not a number"}, BadArgs{"--color 1,,3", "is not a number"},
        BadArgs{"--color nan,0,0", "finite"}, BadArgs{"--color inf,0,0", "finite"},
        BadArgs{"--color 1,1,1 --wavelengths 780:380:5", "reversed"},
        BadArgs{"--color 1,1,1 --wavelengths 380:780:0", "step must be positive"},
        BadArgs{"--color 1,1,1 --wavelengths 300:780:5", "360..830"},
        BadArgs{"--color 1,1,1 --wavelengths 380:780", "start:end:step"},
        BadArgs{"--color 1,1,1 --wavelengths 380:781:5", "whole number"},
        BadArgs{"--color 1,1,1 --observer cie2000", "--observer"},
        BadArgs{"--color 1,1,1 --illuminant F99", "unknown illuminant 'F99'"},
        BadArgs{"--color 1,1,1 --mode glossy",
                "--mode: 'glossy' (valid: auto, emission, reflectance)"},
        BadArgs{"--color 1,1,1 --filter 1.5", "--filter"},
        BadArgs{"--color 1,1,1 --filter x", "--filter"},
        BadArgs{"--color 1,1,1 --format xml", "--format: 'xml' (valid: csv, json)"},
        BadArgs{"--color 1,1,1 --model wavy", "--model: unknown model 'wavy'"},
        BadArgs{"--color 1,1,1 --emission-basis D6x", "--emission-basis: unknown emission basis"},
        BadArgs{"--color 1,1,1 --bogus", "bogus"}, BadArgs{"", "nothing to do"}));

// --model smooth through the binary: the same promises (exact, non-negative, <= 1), the model
// in the JSON, and smoother than the paper's spectrum of the same colour (sum of squared
// first differences, computed here).
TEST(CliColor, SmoothModelIsExactBoundedAndSmoother) {
  auto slope = [](const std::vector<double>& v) {
    double s = 0;
    for (std::size_t i = 0; i + 1 < v.size(); ++i) s += (v[i + 1] - v[i]) * (v[i + 1] - v[i]);
    return s;
  };
  for (const char* mode : {"emission", "reflectance"}) {
    const std::string args = std::string("--color 0.21,0.72,0.15 --format json --mode ") + mode;
    auto smooth = run(args + " --model smooth"), paper = run(args + " --model paper");
    ASSERT_EQ(smooth.exit_code, 0) << smooth.err;
    ASSERT_EQ(paper.exit_code, 0) << paper.err;
    Json j = Json::parse(smooth.out), p = Json::parse(paper.out);
    EXPECT_EQ(j["model"], "smooth");
    EXPECT_EQ(p["model"], "paper");
    EXPECT_FALSE(j.contains("filter"));  // the edge filter is the paper model's only
    EXPECT_TRUE(p.contains("filter"));
    std::vector<double> nm = j["wavelengths_nm"], v = j["values"];
    const bool refl = std::string(mode) == "reflectance";
    for (double x : v) {
      EXPECT_GE(x, 0);
      if (refl) {
        EXPECT_LE(x, 1.0);
      }
    }
    auto got = refl
                   ? e2e::integrate(nm, v, "cie1931_2deg_cmf_1nm.csv", "cie_illuminant_d65_1nm.csv")
                   : e2e::integrate(nm, v, "cie1931_2deg_cmf_1nm.csv");
    std::vector<double> t = j["target_xyz"];
    EXPECT_LE(e2e::rel_err(got, t[0], t[1], t[2]), 1e-6) << mode;  // float: the table's
    EXPECT_LT(slope(v), 0.5 * slope(p["values"].get<std::vector<double>>())) << mode;
  }
}

// --emission-basis D65: white light becomes the CIE D65 table (sampled at 5 nm, scaled), for
// both models, solved (to double precision) and from the table (its white node: to float
// precision); the reported basis is in the JSON.
TEST(CliColor, WhiteLightWithTheD65BasisIsTheD65Table) {
  const e2e::Table t = e2e::read_table("cie_illuminant_d65_1nm.csv", {"value"});
  auto table_at = [&](double nm) {  // the 1 nm table at a whole wavelength
    for (std::size_t k = 0; k < t.nm.size(); ++k)
      if (t.nm[k] == nm) return t.cols[0][k];
    return -1.0;
  };
  for (const char* model : {"paper", "smooth"})
    for (const char* method : {"exact", "table"}) {
      auto r = run(std::string("--color 2,2,2 --format json --emission-basis D65 --model ") +
                   model + " --method " + method);
      ASSERT_EQ(r.exit_code, 0) << r.err;
      Json j = Json::parse(r.out);
      EXPECT_EQ(j["emission_basis"], "D65");
      std::vector<double> nm = j["wavelengths_nm"], v = j["values"];
      ASSERT_EQ(nm[36], 560);
      const double scale = v[36] / table_at(560);
      const double tol = std::string(method) == "exact" ? 1e-9 : 1e-6;
      for (std::size_t i = 0; i < nm.size(); ++i) {
        EXPECT_NEAR(v[i], scale * table_at(nm[i]), tol * v[36])
            << model << " " << method << " " << nm[i];
      }
    }
}

TEST(CliColor, ConfigComesFromOcioEnvironmentWhenSet) {
  auto r = run("--color 0.5,0.5,0.5 --colorspace srgb_tx",
               "OCIO=" SPECTRALIZE_SOURCE_DIR "/ocio_configs/spectralize.ocio");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  r = run("--color 0.5,0.5,0.5", "OCIO=/nonexistent/x.ocio");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("$OCIO=/nonexistent/x.ocio"), std::string::npos) << r.err;
}

}  // namespace
