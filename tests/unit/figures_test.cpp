// make_figures (figures/figures.h), called as a library: it returns a figure per sphere with
// the numbers it prints; the spectral half reflects the colour the RGB half does under the light
// the spectra were made for (D65 for the surface; the paper's light for itself), and under A the
// RGB renderer's light is A's colour in the space with D65's calibration (docs/DESIGN.md §3),
// computed here by the test's own integration; its files are the figures and nothing else. The
// binary's command line and the written pixels are tests/e2e/figures_test.cpp's.

#include "figures/figures.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <regex>
#include <set>
#include <sstream>
#include <string>

#include "file_test_support.h"
#include "spectralize/core/spectralizer.h"
#include "test_support.h"

namespace spectralize::figures {
namespace {

// What make_figures printed for a sphere: "NAME: max dE2000 V (mean M over P mirror pixel
// pairs; TITLE; reflected RGB r,g,b (RGB render) vs r,g,b (spectral render))".
struct Printed {
  double max = 0, mean = 0;
  std::size_t pairs = 0;
  std::array<double, 3> rgb_render{}, spectral_render{};
};

std::map<std::string, Printed> parse(const std::string& out) {
  std::map<std::string, Printed> lines;
  const std::string num = R"(([-0-9.eE+]+))";
  const std::regex line(R"((fig\w+): max dE2000 )" + num + " \\(mean " + num + " over (\\d+) " +
                        "mirror pixel pairs; [^;]*; reflected RGB " + num + "," + num + "," + num +
                        " \\(RGB render\\) vs " + num + "," + num + "," + num);
  for (std::sregex_iterator it(out.begin(), out.end(), line), end; it != end; ++it) {
    const std::smatch& m = *it;
    Printed p{std::stod(m[2]), std::stod(m[3]), std::stoul(m[4]), {}, {}};
    for (int c = 0; c < 3; ++c) {
      p.rgb_render[c] = std::stod(m[5 + c]);
      p.spectral_render[c] = std::stod(m[8 + c]);
    }
    lines[m[1]] = p;
  }
  return lines;
}

// Printed at 4 significant digits.
void expect_4_digits(const std::array<double, 3>& got, const std::array<double, 3>& want,
                     const std::string& what) {
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(got[c], want[c], 6e-4 * std::abs(want[c]) + 1e-12) << what << " channel " << c;
}

TEST(MakeFiguresSlow, ReturnsWhatItPrintsAndTheHalvesAgreeUnderTheirOwnLight) {
  const test::TempDir dir("figures_unit");
  const std::string outdir = dir / "figs";  // made by make_figures
  std::ostringstream out;
  const std::vector<SphereFigure> figures = make_figures(outdir, out);
  const std::map<std::string, Printed> printed = parse(out.str());

  const std::vector<std::pair<std::string, std::string>> want = {
      {"fig2_sphere_light", "paper light"},
      {"fig4_sphere_surface", "D65"},
      {"fig5_sphere_surface_A", "A"},
      {"fig6_sphere_surface_F11", "FL11"}};
  ASSERT_EQ(figures.size(), want.size()) << out.str();
  // Half the disc of a 512-pixel sphere: pi 256^2 / 2 mirror pairs, to the edge's pixels.
  const double half_disc = std::numbers::pi * 256 * 256 / 2;
  for (std::size_t i = 0; i < want.size(); ++i) {
    const SphereFigure& f = figures[i];
    SCOPED_TRACE(f.name);
    EXPECT_EQ(f.name, want[i].first);
    EXPECT_EQ(f.light, want[i].second);
    EXPECT_NEAR(static_cast<double>(f.pairs), half_disc, 0.01 * half_disc);
    EXPECT_LE(f.mean_delta_e, f.max_delta_e);
    ASSERT_EQ(printed.count(f.name), 1u) << out.str();
    const Printed& p = printed.at(f.name);
    EXPECT_EQ(p.pairs, f.pairs);
    EXPECT_NEAR(p.max, f.max_delta_e, 1e-3 * f.max_delta_e + 1e-12);
    EXPECT_NEAR(p.mean, f.mean_delta_e, 1e-3 * f.mean_delta_e + 1e-12);
  }
  // The paper's claim: under the light the spectra were made for, the halves are the same
  // colour; under other lights an RGB renderer and a spectral one differ.
  EXPECT_LE(figures[0].max_delta_e, 0.01);
  EXPECT_LE(figures[1].max_delta_e, 0.01);
  EXPECT_GT(figures[2].mean_delta_e, 0.5);
  EXPECT_GT(figures[3].mean_delta_e, 0.5);

  // The reflected colour at n.v = 1: albedo times light, per channel, for the RGB renderer; the
  // spectral renderer's in the same space agrees under D65 and the paper's light.
  const std::array<double, 3> surface{0.21, 0.72, 0.15}, light{6000, 5000, 1000};
  expect_4_digits(printed.at("fig2_sphere_light").rgb_render, light, "fig2 RGB");
  expect_4_digits(printed.at("fig2_sphere_light").spectral_render, light, "fig2 spectral");
  expect_4_digits(printed.at("fig4_sphere_surface").rgb_render, surface, "fig4 RGB");
  expect_4_digits(printed.at("fig4_sphere_surface").spectral_render, surface, "fig4 spectral");
  // Under A: the RGB renderer's light is A's white (rho == 1 under A, Y = 1) in the fixed D65
  // calibration, as Linear Rec.709.
  const SpectralizerSettings defaults;
  const Observer& obs = Observer::get(defaults.observer);
  const std::vector<double> ones(defaults.grid.size(), 1.0);
  const Illuminant d65 = Illuminant::get("D65"), a = Illuminant::get("A");
  const Xyz w65 = test::reference_xyz(defaults.grid, ones, obs, &d65.spd);
  const Xyz wa = test::reference_xyz(defaults.grid, ones, obs, &a.spd);
  const Xyz a_rgb =
      test::mul(test::inverse(test::kRec709ToXyz),
                hadamard(wa, {kWhiteD65.X / w65.X, kWhiteD65.Y / w65.Y, kWhiteD65.Z / w65.Z}));
  EXPECT_GT(a_rgb.X, a_rgb.Z);  // A is warm
  expect_4_digits(printed.at("fig5_sphere_surface_A").rgb_render,
                  {surface[0] * a_rgb.X, surface[1] * a_rgb.Y, surface[2] * a_rgb.Z}, "fig5 RGB");

  // The figures, a difference map per sphere, and nothing else (no temporary files).
  std::set<std::string> files;
  for (const auto& e : std::filesystem::directory_iterator(outdir))
    files.insert(e.path().filename().string());
  std::set<std::string> expected = {"fig1_light_spectrum.png", "fig3_surface_spectrum.png"};
  for (const auto& [name, l] : want) {
    expected.insert(name + ".png");
    expected.insert(name + "_dE.png");
  }
  EXPECT_EQ(files, expected);
}

TEST(MakeFigures, AnOutputFolderThatCannotBeMadeIsNamed) {
  const test::TempDir dir("figures_unit");
  const std::string blocker = dir / "file";
  std::ofstream(blocker) << "x";
  std::ostringstream out;
  test::expect_error_mentioning([&] { make_figures(blocker + "/figs", out); },
                                {blocker + "/figs", "cannot create"}, "a file in the way");
  EXPECT_EQ(out.str(), "");
}

}  // namespace
}  // namespace spectralize::figures
