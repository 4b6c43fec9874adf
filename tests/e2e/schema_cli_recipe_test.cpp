// The CLI and the plugin's recipes accept and refuse exactly the same values: for every setting
// of the schema that recipes take, a good and a bad value go to the real binary as a flag and
// to stock oiiotool as a recipe key, and both must agree (and every refusal names the value).

#include <gtest/gtest.h>

#include <fstream>
#include <map>

#include "cli_support.h"
#include "settings/settings.h"

namespace {

using e2e::run;

const std::string kImages = SPECTRALIZE_SOURCE_DIR "/testimages/";

// A good and a bad value per recipe key, independent of the schema (a new key must be added).
const std::map<std::string, std::pair<std::string, std::string>> kValues = {
    {"colorspace", {"sRGB - Texture", "NoSuchSpace"}},
    {"mode", {"reflectance", "glossy"}},
    {"wavelengths", {"400:700:10", "380:781:5"}},
    {"observer", {"cie1964", "cie2000"}},
    {"illuminant", {"D50", "F99"}},
    {"model", {"smooth", "wavy"}},
    {"filter", {"0.5", "1.5"}},
    {"curvature", {"20", "-3"}},
    {"emission_basis", {"D65", "D6x"}},
    {"format", {"float", "double"}},
    {"compression", {"zip:6", "bogus"}},
    {"tile", {"32", "7"}},
    {"method", {"exact", "fast"}},
    {"preview_colorspace", {"ACEScg", "NoSuchSpace"}},
    {"cache", {"cache", ""}},
    {"threads", {"1", "-2"}},
    {"config", {SPECTRALIZE_SOURCE_DIR "/ocio_configs/spectralize.ocio", "/no/such.ocio"}},
};

TEST(SchemaCliRecipeSlow, AcceptAndRefuseTheSameValues) {
  e2e::Scratch s("spectralize_schema");
  const std::string in = kImages + "grey_ramp8.png";
  for (const spectralize::SettingSpec& spec : spectralize::settings_schema()) {
    if (!spec.recipe || !spec.applies(spectralize::kImage)) continue;
    SCOPED_TRACE(std::string(spec.key));
    auto it = kValues.find(std::string(spec.key));
    ASSERT_NE(it, kValues.end()) << "add values for the new recipe key to this test";
    for (const std::string& value : {it->second.first, it->second.second}) {
      if (value.empty()) continue;
      SCOPED_TRACE(value);
      const auto cli =
          run(in + " -o " + (s / "cli.exr") + " -q " + std::string(spec.flag) + " '" + value + "'");
      std::ofstream(s / "r.spectral")
          << "{\"source\": \"" << in << "\", \"" << spec.key << "\": \"" << value << "\"}";
      const std::string log = s / "tool.txt";
      const int status = std::system(
          ("OIIO_LIBRARY_PATH=" SPECTRALIZE_PLUGIN_DIR " " SPECTRALIZE_TOOL_ENV " oiiotool " +
           (s / "r.spectral") + " -o " + (s / "recipe.exr") + " >" + log + " 2>&1")
              .c_str());
      const bool recipe_ok = WIFEXITED(status) && WEXITSTATUS(status) == 0;
      EXPECT_EQ(cli.exit_code == 0, recipe_ok) << cli.err << e2e::slurp(log);
      if (!recipe_ok) {
        EXPECT_NE(e2e::slurp(log).find(value), std::string::npos) << e2e::slurp(log);
      }
      if (cli.exit_code != 0) {
        EXPECT_NE(cli.err.find(value), std::string::npos) << cli.err;
      }
    }
  }
}

}  // namespace
