// The spectral-to-RGB conversion (pipeline/rgb_conversion.h) of a decided plan: a constant
// reflectance is the grey of its value (the white balance of docs/DESIGN.md §3: rho == 1 gives
// the white, RGB (1, 1, 1), so rho gives (rho, rho, rho) in a linear space), alpha passes
// through, and what the output cannot store is counted and warned about, options spelt as the
// caller spells them. Oracles: the definition of a reflectance and the pixels each case makes.

#include "pipeline/rgb_conversion.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "file_test_support.h"
#include "imagefile/output_formats.h"
#include "pipeline/job_plan.h"
#include "spectralize/core/error.h"

namespace spectralize {
namespace {

const LogFn kQuiet = [](int, const std::string&) {};

// Channel names of bands 400..700 nm every 10 nm, `prefix` T (reflectance) or S0 (emission).
std::vector<std::string> bands(const std::string& prefix) {
  std::vector<std::string> names;
  for (int nm = 400; nm <= 700; nm += 10) names.push_back(prefix + "." + std::to_string(nm) + "nm");
  return names;
}

TEST(RgbConversion, AConstantReflectanceIsTheGreyOfItsValue) {
  std::vector<std::string> names = bands("T");
  names.push_back("A");
  OIIO::ImageSpec spec = test::spec_of(names, OIIO::TypeFloat, 2, 1);
  spec.alpha_channel = static_cast<int>(names.size()) - 1;
  Settings s;
  s.half = false;
  s.colorspace = "Linear Rec.709 (sRGB)";
  const JobPlan plan =
      planned_input(plan_to_rgb(s, "out.exr", true, true, OptionNames{"--", "-o"}), "in.exr", spec);
  RgbConversion conversion(plan, spec, "out.exr", output_format_for("out.exr"), kQuiet);
  ASSERT_EQ(conversion.output_channels(), 4);
  const int n = static_cast<int>(names.size());
  std::vector<float> in(2 * n), out(2 * 4);
  for (int k = 0; k + 1 < n; ++k) in[k] = 0.4f, in[n + k] = 1.0f;
  in[n - 1] = 0.5f, in[2 * n - 1] = 1.0f;
  conversion.convert(in.data(), 2, out.data());
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(out[c], 0.4, 1e-5 * 0.4) << c;  // float samples: 1e-5 (DESIGN §3)
    EXPECT_NEAR(out[4 + c], 1.0, 1e-5) << c;    // the perfect reflector is the white
  }
  EXPECT_EQ(out[3], 0.5f);
  const ToRgbReport& rep = conversion.finish(kQuiet);
  EXPECT_EQ(rep.kind, "reflective");
  EXPECT_EQ(rep.bands, 31);
  EXPECT_EQ(rep.first_nm, 400);
  EXPECT_EQ(rep.last_nm, 700);
  EXPECT_EQ(rep.invalid_pixels, 0u);
}

TEST(RgbConversion, WhatTheOutputCannotStoreIsCountedAndNamedAsTheCallerSpellsIt) {
  const OIIO::ImageSpec spec = test::spec_of(bands("S0"), OIIO::TypeFloat, 3, 1);
  for (const OptionNames& names : {OptionNames{"--", "-o"}, OptionNames{"", "output"}}) {
    Settings s;  // half samples (the default of OpenEXR)
    const JobPlan plan =
        planned_input(plan_to_rgb(s, "out.exr", true, true, names), "in.exr", spec);
    RgbConversion conversion(plan, spec, "out.exr", output_format_for("out.exr"), kQuiet);
    const int n = spec.nchannels;
    std::vector<float> in(3 * n, 0.1f), out(3 * 3);
    in[0] = std::numeric_limits<float>::quiet_NaN();  // pixel 0: a NaN sample
    for (int k = 0; k < n; ++k) in[n + k] = 1e7f;     // pixel 1: far beyond HALF's 65504
    conversion.convert(in.data(), 3, out.data());
    const ToRgbReport& rep = conversion.finish(kQuiet);
    EXPECT_EQ(rep.invalid_pixels, 1u);
    EXPECT_EQ(rep.half_overflow_pixels, 1u);
    for (float v : out) EXPECT_TRUE(std::isfinite(v));
    std::string all;
    for (const std::string& w : rep.warnings) all += w + "\n";
    EXPECT_NE(all.find("'in.exr': 1 pixels have NaN"), std::string::npos) << all;
    EXPECT_NE(all.find("use " + names("format") + " float"), std::string::npos) << all;
  }
}

TEST(RgbConversion, NeedsAPlanDecidedForASpectralInput) {
  const JobPlan undecided = plan_to_rgb(Settings{}, "out.exr", false, false, OptionNames{});
  EXPECT_THROW(RgbConversion(undecided, test::spec_of(bands("T")), "out.exr", nullptr, kQuiet),
               Error);
}

}  // namespace
}  // namespace spectralize
