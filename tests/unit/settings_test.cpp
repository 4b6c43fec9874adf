// The settings schema (settings/settings.h) against independent truths: for every setting, a value
// that changes the spectra (found by computing spectra, not by asking the schema) must change
// the node cache's key and show in the report's settings and the EXR attributes; every setting
// refuses an empty value and its own invalid example; canonical texts parse back to themselves.

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>
#include <string>

#include "colour/colour_space.h"
#include "core/spectral_table.h"
#include "pipeline/spectral_image_layout.h"
#include "settings/settings.h"
#include "spectralize/core/error.h"
#include "spectralize/core/spectralizer.h"
#include "spectralize/core/spectrum_model.h"

namespace spectralize {
namespace {

// For every schema key: a valid value other than the default, and an invalid one. Written here,
// independently of the schema: a new setting without an entry fails the test below.
const std::map<std::string, std::pair<std::string, std::string>> kExamples = {
    {"colorspace", {"ACEScg", ""}},  // validated by the config, at use
    {"mode", {"reflectance", "glossy"}},
    {"wavelengths", {"400:700:10", "380:781:5"}},
    {"observer", {"cie1964", "cie2000"}},
    {"illuminant", {"A", "F99"}},
    {"model", {"smooth", "wavy"}},
    {"filter", {"0.5", "1.5"}},
    {"curvature", {"20", "-3"}},
    {"emission_basis", {"D65", "D6x"}},
    {"format", {"float", "double"}},
    {"print_format", {"json", "xml"}},
    {"compression", {"piz", "zip:12"}},
    {"tile", {"64", "7"}},
    {"method", {"exact", "fast"}},
    {"preview_colorspace", {"ACEScg", ""}},  // validated by the config, at use
    {"reflected", {"as-lit", "warm"}},
    {"display", {"sRGB", ""}},
    {"view", {"Standard", ""}},
    {"plot_scale", {"log", "cubic"}},
    {"name_pattern", {"{dir}/{stem}_spectral.exr", "{stem}.png"}},
    {"data_names", {"+msk,-metal", "nor mal"}},
    {"colour_names", {"+glow2:emission,+alb", "+sky:light"}},
    {"data", {"copy", "keep"}},
    {"jobs", {"2", "-1"}},
    {"cache", {"/tmp/cache", ""}},
    {"threads", {"3", "-2"}},
    {"config", {"/some/config.ocio", ""}},
};

// The spectra of a few colours under `s` (mode resolved), as one vector.
std::vector<double> spectra(const Settings& s) {
  const Spectralizer sp(s.spectral);
  std::vector<double> out;
  for (const Xyz& c :
       {Xyz{0.2, 0.3, 0.4}, Xyz{0.4, 0.3, 0.1}, Xyz{0.9505, 1.0, 1.089}, Xyz{0.1, 0.05, 0.3}}) {
    const SpectrumResult r = sp.spectralize(c);
    out.insert(out.end(), r.values.begin(), r.values.end());
  }
  return out;
}

bool differ(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size()) return true;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (std::abs(a[i] - b[i]) > 1e-9 * (1 + std::abs(a[i]))) return true;
  return false;
}

// The mode as the image job resolves it for float data.
void resolve_mode(Settings& s) {
  s.spectral.mode = s.mode == ModeChoice::reflectance ? Mode::reflectance : Mode::emission;
}

std::set<std::string> attributes(const Settings& s) {
  const ColourSpaces spaces = ColourSpaces::load();
  OIIO::ImageSpec input(4, 4, 3, OIIO::TypeFloat);
  auto layout = spectral_exr_layout({input, false, s, "Linear Rec.709 (sRGB)",
                                     "Linear Rec.709 (sRGB)", spaces, "2000:01:01 00:00:00"});
  std::set<std::string> out;
  for (const auto& p : layout->spec().extra_attribs)
    if (p.name().string().rfind("spectralize:", 0) == 0)
      out.insert(p.name().string() + "=" + p.get_string());
  return out;
}

TEST(SettingsSchema, EveryKeyHasExamplesAndRefusesBadValues) {
  for (const SettingSpec& spec : settings_schema()) {
    SCOPED_TRACE(std::string(spec.key));
    auto it = kExamples.find(std::string(spec.key));
    ASSERT_NE(it, kExamples.end()) << "add examples for the new setting to this test";
    Settings s;
    EXPECT_THROW(apply_setting(s, spec, "", spec.flag), Error);
    EXPECT_NO_THROW(apply_setting(s, spec, it->second.first, spec.flag));
    if (!it->second.second.empty()) {
      Settings t;
      try {
        apply_setting(t, spec, it->second.second, spec.flag);
        ADD_FAILURE() << "accepted '" << it->second.second << "'";
      } catch (const Error& e) {
        // The message names the flag and the value.
        EXPECT_NE(std::string(e.what()).find(spec.flag), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find(it->second.second), std::string::npos) << e.what();
      }
    }
    // The canonical text parses back to the same canonical text.
    Settings u;
    apply_setting(u, spec, spec.format(s), spec.flag);
    EXPECT_EQ(spec.format(u), spec.format(s));
  }
}

// Truth: if a setting changes the spectra, the cache key must change (else a cached table made
// for other settings would be reused: exact colours, wrong spectra), and the report and the EXR
// attributes must say what changed. Checked from several starting points, because some settings
// only matter there (the illuminant for reflectances, the curvature for the smooth model, the
// edge filter for the paper's model): every registered model, in both modes.
TEST(SettingsSchema, EverySettingThatShapesSpectraIsInTheCacheKeyReportAndAttributes) {
  std::vector<Settings> bases;
  for (const ModelInfo& model : spectrum_models())
    for (ModeChoice mode : {ModeChoice::emission, ModeChoice::reflectance}) {
      Settings b;
      b.spectral.model = std::string(model.name);
      b.mode = mode;
      bases.push_back(b);
    }
  bases.emplace_back().spectral.emission_basis = "D65";
  int shaping = 0;
  for (Settings base : bases) {
    resolve_mode(base);
    const auto base_spectra = spectra(base);
    const std::string base_key = table_cache_key(base, "layout");
    for (const SettingSpec& spec : settings_schema()) {
      Settings alt = base;
      apply_setting(alt, spec, kExamples.at(std::string(spec.key)).first, spec.flag);
      resolve_mode(alt);
      if (!differ(spectra(alt), base_spectra)) continue;
      ++shaping;
      SCOPED_TRACE(std::string(spec.key) + " from mode " + std::string(to_string(base.mode)) +
                   ", model " + base.spectral.model);
      EXPECT_NE(table_cache_key(alt, "layout"), base_key);
      EXPECT_NE(describe_settings(alt, kImage), describe_settings(base, kImage));
      EXPECT_NE(attributes(alt), attributes(base));
    }
  }
  EXPECT_GE(shaping, 20);  // the check above is not vacuous
}

TEST(SettingsSchema, FlagsMapToTheirCommands) {
  EXPECT_EQ(find_setting_for_flag("--format", kColor)->key, "print_format");
  EXPECT_EQ(find_setting_for_flag("--format", kImage)->key, "format");
  EXPECT_EQ(find_setting_for_flag("-d", kToRgb)->key, "format");
  EXPECT_EQ(find_setting_for_flag("--report", kImage), nullptr);  // not a setting
  EXPECT_EQ(find_setting_for_flag("--wavelengths", kToRgb), nullptr);
  EXPECT_EQ(find_setting_for_flag("--colorconfig", kColor)->key, "config");
  EXPECT_NE(flag_commands("--threads") & kImage, 0u);
  EXPECT_EQ(flag_commands("--threads") & kColor, 0u);
}

}  // namespace
}  // namespace spectralize
