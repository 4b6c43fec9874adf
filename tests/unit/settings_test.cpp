// The settings schema and its functions (settings/settings.h) against independent truths: for
// every setting, a value that changes the spectra (found by computing spectra, not by asking the
// schema) must change the node cache's key, show in the report's settings and the EXR
// attributes, and change the settings a written file records (file_settings); how a job runs
// never does; every setting refuses an empty value and its own invalid example; canonical texts
// parse back to themselves; each key and flag finds its setting and nothing else does; the value
// recorded for the mode is the mode resolved, never "auto"; a command's description holds only
// the settings that apply to it and matter.

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>
#include <string>

#include "colour/colour_space.h"
#include "core/tables/spectral_table.h"
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
    {"rgb_to_xyz", {"0.64,0.33,0.3,0.6,0.15,0.06,D65", "1,2,3"}},
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
                   ", model " + std::string(base.spectral.model.name()));
      EXPECT_NE(table_cache_key(alt, "layout"), base_key);
      EXPECT_NE(describe_settings(alt, kImage), describe_settings(base, kImage));
      EXPECT_NE(attributes(alt), attributes(base));
    }
  }
  EXPECT_GE(shaping, 20);  // the check above is not vacuous
}

// Truth: a setting the user gives is refused as shaping nothing exactly when it changes no
// spectrum (found by computing spectra, not by asking the schema), for every model and mode; a
// mode left to each input refuses only what shapes neither mode.
TEST(SettingsSchema, AGivenSettingIsRefusedExactlyWhenItShapesNoSpectrum) {
  int refused = 0;
  for (const ModelInfo& model : spectrum_models())
    for (Mode mode : {Mode::emission, Mode::reflectance}) {
      Settings base;
      base.spectral.model = model.name;
      base.spectral.mode = mode;
      EXPECT_EQ(ineffective_setting(base, mode), nullptr) << "nothing given, nothing refused";
      const auto base_spectra = spectra(base);
      for (const SettingSpec& spec : settings_schema()) {
        if (!spec.spectral || spec.key == "mode" || spec.key == "model") continue;
        SCOPED_TRACE(std::string(spec.key) + " on " + std::string(model.name) + ", " +
                     std::string(to_string(mode)));
        Settings alt = base;
        apply_setting(alt, spec, kExamples.at(std::string(spec.key)).first, spec.flag);
        EXPECT_TRUE(was_given(alt, spec));
        const bool shapes = differ(spectra(alt), base_spectra);
        const SettingSpec* named = ineffective_setting(alt, mode);
        EXPECT_EQ(named == &spec, !shapes) << "shapes the spectra: " << shapes;
        refused += named == &spec;
        // Left to each input: refused only when it shapes neither mode's spectra.
        Settings other = alt, other_base = base;
        other.spectral.mode = other_base.spectral.mode =
            mode == Mode::emission ? Mode::reflectance : Mode::emission;
        const bool shapes_other = differ(spectra(other), spectra(other_base));
        EXPECT_EQ(ineffective_setting(alt, std::nullopt) == &spec, !shapes && !shapes_other);
      }
    }
  // The filter and the curvature on the models without them, the basis on reflectances, the
  // illuminant on light: the check above is not vacuous.
  EXPECT_GE(refused, 16);
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

TEST(SettingsSchema, EveryKeyFindsItsSettingAndNothingElseDoes) {
  for (const SettingSpec& spec : settings_schema()) EXPECT_EQ(find_setting(spec.key), &spec);
  // Flags, other spellings and unknown words are not keys.
  for (const char* word : {"", "--mode", "Mode", "mode ", "emission-basis", "nosuchsetting"})
    EXPECT_EQ(find_setting(word), nullptr) << word;
}

TEST(SettingsSchema, ModesAndPlotScalesAreSpelledAsTheirSettingsParseThem) {
  const SettingSpec& mode = *find_setting("mode");
  for (const auto& [m, text] : {std::pair{ModeChoice::automatic, "auto"},
                                {ModeChoice::emission, "emission"},
                                {ModeChoice::reflectance, "reflectance"}}) {
    EXPECT_EQ(to_string(m), text);
    Settings s;
    s.mode = m == ModeChoice::emission ? ModeChoice::reflectance : ModeChoice::emission;
    apply_setting(s, mode, to_string(m), "--mode");
    EXPECT_EQ(s.mode, m) << text;
  }
  const SettingSpec& scale = *find_setting("plot_scale");
  for (const auto& [p, text] : {std::pair{PlotScale::linear, "linear"},
                                {PlotScale::log, "log"},
                                {PlotScale::normalized, "normalized"}}) {
    EXPECT_EQ(to_string(p), text);
    Settings s;
    s.plot_scale = p == PlotScale::log ? PlotScale::linear : PlotScale::log;
    apply_setting(s, scale, to_string(p), "--plot-scale");
    EXPECT_EQ(s.plot_scale, p) << text;
  }
}

TEST(SettingsSchema, TheModeRecordedIsTheModeResolvedNeverAuto) {
  const SettingSpec& mode = *find_setting("mode");
  Settings s;  // asked: auto
  for (const Mode resolved : {Mode::emission, Mode::reflectance}) {
    s.spectral.mode = resolved;
    const std::string want = resolved == Mode::emission ? "emission" : "reflectance";
    EXPECT_EQ(mode.format(s), "auto");  // what was asked
    EXPECT_EQ(setting_value(mode, s), want);
    for (const auto& [key, value] : describe_settings(s, kImage))
      if (key == "mode") {
        EXPECT_EQ(value, want);
      }
    for (const auto& [spec, value] : file_settings(s))
      if (spec->key == "mode") {
        EXPECT_EQ(value, want);
      }
  }
  // Every other setting's recorded value is its canonical text.
  for (const SettingSpec& spec : settings_schema())
    if (spec.key != "mode") {
      EXPECT_EQ(setting_value(spec, s), spec.format(s)) << spec.key;
    }
}

// What shapes a spectrum physically: its grid, the observer, the model, the mode, and the
// illuminant of a reflectance or the basis of an emission. Each is recorded in a written file.
TEST(SettingsSchema, WhatShapesTheSpectraChangesTheSettingsAFileRecords) {
  for (const ModeChoice mode : {ModeChoice::emission, ModeChoice::reflectance}) {
    Settings base;
    base.mode = mode;
    resolve_mode(base);
    const auto base_file = file_settings(base);
    std::vector<std::pair<std::string, std::string>> changes = {
        {"wavelengths", "400:700:10"},
        {"observer", "cie1964"},
        {"model", "smooth"},
        {"mode", mode == ModeChoice::emission ? "reflectance" : "emission"}};
    changes.emplace_back(mode == ModeChoice::emission ? std::pair{"emission_basis", "D65"}
                                                      : std::pair{"illuminant", "A"});
    for (const auto& [key, value] : changes) {
      SCOPED_TRACE(key + " from " + std::string(to_string(mode)));
      Settings alt = base;
      apply_setting(alt, *find_setting(key), value, key);
      resolve_mode(alt);
      EXPECT_NE(file_settings(alt), base_file);
    }
  }
}

TEST(SettingsSchema, HowAJobRunsAndWhereItsOutputsGoNeverChangeWhatAFileRecords) {
  Settings base;
  resolve_mode(base);
  const auto base_file = file_settings(base);
  const std::string base_key = table_cache_key(base, "layout");
  for (const char* key : {"threads", "jobs", "cache", "config", "name_pattern", "data"}) {
    Settings alt = base;
    apply_setting(alt, *find_setting(key), kExamples.at(key).first, key);
    EXPECT_EQ(file_settings(alt), base_file) << key;
    EXPECT_EQ(table_cache_key(alt, "layout"), base_key) << key;
  }
  // What shapes the written file but not its spectra is recorded too: samples, compression,
  // tiles.
  for (const char* key : {"format", "compression", "tile"}) {
    Settings alt = base;
    apply_setting(alt, *find_setting(key), kExamples.at(key).first, key);
    EXPECT_NE(file_settings(alt), base_file) << key;
  }
  // In schema order.
  std::size_t last = 0;
  for (const auto& [spec, value] : file_settings(base)) {
    const std::size_t at = static_cast<std::size_t>(spec - settings_schema().data());
    EXPECT_GE(at, last) << spec->key;
    last = at;
  }
  // The node table's layout is part of the cache key.
  EXPECT_NE(table_cache_key(base, "other layout"), base_key);
  EXPECT_EQ(table_cache_key(base, "layout"), base_key);
}

TEST(SettingsSchema, ACommandsDescriptionHoldsWhatAppliesToItAndMatters) {
  Settings s;
  resolve_mode(s);  // emission: the illuminant does not matter
  auto keys = [](const std::vector<std::pair<std::string, std::string>>& d) {
    std::set<std::string> out;
    for (const auto& [k, v] : d) out.insert(k);
    return out;
  };
  const auto image = keys(describe_settings(s, kImage));
  EXPECT_TRUE(image.count("wavelengths"));
  EXPECT_TRUE(image.count("format"));
  EXPECT_FALSE(image.count("print_format"));  // --color's --format
  EXPECT_FALSE(image.count("reflected"));     // --to-rgb's
  EXPECT_FALSE(image.count("illuminant"));    // emission
  EXPECT_FALSE(image.count("colorspace"));    // not given: decided per file
  const auto to_rgb = keys(describe_settings(s, kToRgb));
  EXPECT_TRUE(to_rgb.count("reflected"));
  EXPECT_FALSE(to_rgb.count("wavelengths"));  // the file's own grid
  const auto color = keys(describe_settings(s, kColor));
  EXPECT_TRUE(color.count("print_format"));
  EXPECT_FALSE(color.count("format"));
  s.spectral.mode = Mode::reflectance;
  s.colorspace = "ACEScg";
  const auto reflective = keys(describe_settings(s, kImage));
  EXPECT_TRUE(reflective.count("illuminant"));
  EXPECT_TRUE(reflective.count("colorspace"));
  EXPECT_FALSE(reflective.count("emission_basis"));  // emission only
  // The spectral subset: the settings the spectra depend on, none of how files are written.
  const auto spectral = keys(describe_settings(s, kImage, true));
  for (const std::string& k : spectral) EXPECT_TRUE(reflective.count(k)) << k;
  for (const char* k : {"wavelengths", "observer", "illuminant", "model", "mode"})
    EXPECT_TRUE(spectral.count(k)) << k;
  for (const char* k : {"format", "compression", "tile", "colorspace", "threads", "method"})
    EXPECT_FALSE(spectral.count(k)) << k;
}

}  // namespace
}  // namespace spectralize
