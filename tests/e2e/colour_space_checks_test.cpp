// Colour spaces are checked once, the same way, by every front end (docs/guide/colours.md): a
// space of the config no colour converts through (a zero matrix, a NaN in it, a singular one)
// is refused before anything is converted or written, naming the space and the reason: exit 2
// where the command line names it, a failure of the file where the config's file rules or
// roles choose it. Reports and manifests carry the decided space's interop ID and encoding.
// Oracles: the configs written here (what each space's matrix is), the files left behind.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>

#include "cli_support.h"

namespace fs = std::filesystem;
using e2e::run;
using Json = nlohmann::json;

namespace {

const std::string kImages = SPECTRALIZE_SOURCE_DIR "/testimages/";
const std::string kShipped = SPECTRALIZE_SOURCE_DIR "/ocio_configs/spectralize.ocio";
const std::string kPluginEnv = "OIIO_LIBRARY_PATH=" SPECTRALIZE_PLUGIN_DIR " " SPECTRALIZE_TOOL_ENV;

// The shipped config plus three spaces no colour converts through, a file rule that gives
// files named *_broken* the first, and (with `role`) the scene_linear role naming it.
std::string broken_config(bool role) {
  std::string text = e2e::slurp(kShipped);
  text = std::regex_replace(text, std::regex("(file_rules:\n)"),
                            "$1  - !<Rule> {name: Broken, colorspace: Zero, pattern: "
                            "\"*_broken*\", extension: \"*\"}\n");
  if (role)
    text = std::regex_replace(text, std::regex("scene_linear: [^\n]*"), "scene_linear: Zero");
  // A display's view that ends in it.
  text = std::regex_replace(text, std::regex("( *- !<View> \\{name: Raw, colorspace: Raw\\}\n)"),
                            "$1    - !<View> {name: Broken, colorspace: Zero}\n");
  text = std::regex_replace(text, std::regex("active_views: \\[([^\\]]*)\\]"),
                            "active_views: [$1, Broken]");
  auto space = [](const std::string& name, const std::string& matrix) {
    return "\n  - !<ColorSpace>\n    name: " + name +
           "\n    isdata: false\n    to_scene_reference: !<MatrixTransform> {matrix: [" + matrix +
           ", 0, 0, 0, 1]}\n";
  };
  return text + space("Zero", "0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0") +
         space("NaNs", ".nan, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0") +
         space("Grey", "0.3, 0.3, 0.3, 0, 0.3, 0.3, 0.3, 0, 0.3, 0.3, 0.3, 0");
}

const std::pair<std::string, std::string> kBroken[] = {
    {"Zero", "makes every colour black"}, {"NaNs", "NaN or infinity"}, {"Grey", "singular"}};

void expect_refusal(const e2e::Run& r, int exit_code, const std::string& space,
                    const std::string& why) {
  EXPECT_EQ(r.exit_code, exit_code) << r.err;
  EXPECT_NE(r.err.find("colour space '" + space + "'"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("cannot be used"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(why), std::string::npos) << r.err;
}

TEST(ColourSpaceChecks, EveryCommandRefusesASpaceNoColourConvertsThroughBeforeAnyWork) {
  e2e::Scratch s("spaces");
  const std::string config = s.write("broken.ocio", broken_config(false));
  const std::string cfg = " --config " + config;
  const std::string spectral = s / "ok.exr";
  ASSERT_EQ(run(kImages + "colorchecker_srgb8.png -o " + spectral + cfg + " -q").exit_code, 0);
  fs::create_directories(s / "lib");
  fs::copy_file(kImages + "colorchecker_srgb8.png", s / "lib/a.png");
  for (const auto& [space, why] : kBroken) {
    SCOPED_TRACE(space);
    const std::string named = cfg + " --colorspace " + space;
    // --color: nothing printed.
    e2e::Run r = run("--color 0.5,0.4,0.3" + named);
    expect_refusal(r, 2, space, why);
    EXPECT_EQ(r.out, "");
    // An image, --to-rgb, a table, ingest: nothing written.
    expect_refusal(run(kImages + "colorchecker_srgb8.png -o " + (s / "x.exr") + named), 2, space,
                   why);
    expect_refusal(run("--to-rgb " + spectral + " -o " + (s / "y.exr") + named), 2, space, why);
    expect_refusal(run("table -o " + (s / "t.spztab") + named), 2, space, why);
    expect_refusal(run("ingest " + (s / "lib") + " -o " + (s / "dst") + named), 2, space, why);
    // The preview's space is converted to as well.
    expect_refusal(run(kImages + "colorchecker_srgb8.png -o " + (s / "x.exr") + cfg +
                       " --preview-colorspace " + space),
                   2, space, why);
    for (const char* left : {"x.exr", "y.exr", "t.spztab", "dst"})
      EXPECT_FALSE(fs::exists(s / left)) << left;
  }
}

// A display's view is converted to as well: one ending in such a space is refused by name.
TEST(ColourSpaceChecks, ADisplaysViewEndingInSuchASpaceIsRefused) {
  e2e::Scratch s("spaces");
  const std::string cfg = " --config " + s.write("broken.ocio", broken_config(false));
  ASSERT_EQ(run(kImages + "colorchecker_srgb8.png -o " + (s / "ok.exr") + cfg + " -q").exit_code,
            0);
  const std::string to_rgb = "--to-rgb " + (s / "ok.exr") + " -o " + (s / "y.png") + cfg;
  ASSERT_EQ(run(to_rgb + " --display sRGB --view Standard -q").exit_code, 0);
  fs::remove(s / "y.png");
  const e2e::Run r = run(to_rgb + " --display sRGB --view Broken");
  expect_refusal(r, 2, "Zero", "makes every colour black");
  EXPECT_NE(r.err.find("--display"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(s / "y.png"));
}

TEST(ColourSpaceChecks, ASpaceTheConfigChoosesFailsTheFileItIsChosenFor) {
  e2e::Scratch s("spaces");
  const std::string config = s.write("broken.ocio", broken_config(false));
  fs::create_directories(s / "lib");
  fs::copy_file(kImages + "colorchecker_srgb8.png", s / "lib/a_broken.png");
  fs::copy_file(kImages + "colorchecker_srgb8.png", s / "lib/b.png");
  // The image command: the job fails (1), naming the file, the space and the rule.
  e2e::Run r = run((s / "lib/a_broken.png") + " -o " + (s / "x.exr") + " --config " + config);
  expect_refusal(r, 1, "Zero", "makes every colour black");
  EXPECT_NE(r.err.find("a_broken.png"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("file rule 'Broken'"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(s / "x.exr"));
  // A batch: that file fails, the other is converted.
  r = run("ingest " + (s / "lib") + " -o " + (s / "dst") + " --config " + config);
  expect_refusal(r, 1, "Zero", "makes every colour black");
  EXPECT_TRUE(fs::exists(s / "dst/b.exr"));
  EXPECT_FALSE(fs::exists(s / "dst/a_broken.exr"));
  // A role naming such a space: the config is at fault (1), for every command that uses it.
  const std::string role = s.write("role.ocio", broken_config(true));
  for (const std::string& args :
       {std::string("--color 1,1,1"), kImages + "hdri_sunset_256x128.exr -o " + (s / "y.exr")}) {
    SCOPED_TRACE(args);
    r = run(args + " --config " + role);
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_NE(r.err.find("scene_linear role the colour space 'Zero'"), std::string::npos) << r.err;
    EXPECT_EQ(r.out, "");
  }
  EXPECT_FALSE(fs::exists(s / "y.exr"));
}

TEST(ColourSpaceChecks, ThePluginRefusesASpaceNoColourConvertsThrough) {
  e2e::Scratch s("spaces");
  const std::string config = s.write("broken.ocio", broken_config(false));
  const std::string recipe = s.write("a.spectral", "{\"source\": \"" + kImages +
                                                       "colorchecker_srgb8.png\", \"config\": \"" +
                                                       config + "\", \"colorspace\": \"NaNs\"}");
  const std::string cmd = kPluginEnv + " oiiotool " + recipe + " -o " + (s / "o.exr") + " 2>&1";
  FILE* p = ::popen(cmd.c_str(), "r");
  ASSERT_NE(p, nullptr);
  std::string out;
  char buf[4096];
  while (std::size_t n = std::fread(buf, 1, sizeof buf, p)) out.append(buf, n);
  const int status = ::pclose(p);
  EXPECT_NE(WEXITSTATUS(status), 0) << out;
  EXPECT_NE(out.find("colour space 'NaNs'"), std::string::npos) << out;
  EXPECT_NE(out.find("NaN or infinity"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(s / "o.exr"));
}

}  // namespace

namespace {

// The identity fields of a report or record.
void expect_identity(const Json& j, const Json& id, const Json& source, const Json& encoding) {
  EXPECT_EQ(j.at("colorspace_interop_id"), id) << j.dump();
  EXPECT_EQ(j.at("colorspace_interop_id_source"), source) << j.dump();
  EXPECT_EQ(j.at("colorspace_encoding"), encoding) << j.dump();
}

// Every report, manifest record and --color's JSON names the decided space's interop ID (the
// config's own under OCIO 2.5's built-in configs, else measured, null where neither) and the
// config's encoding. Oracles: the Color Interop Forum's ID of sRGB-encoded Rec.709
// (srgb_rec709_scene) and the encodings the configs state.
TEST(ColourSpaceChecks, ReportsAndManifestsNameTheSpacesInteropIdAndEncoding) {
  e2e::Scratch s("spaces");
  const std::string png = kImages + "colorchecker_srgb8.png";
  struct Case {
    std::string config;  // "" the shipped one
    std::string source;  // where the sRGB texture space's ID comes from
  };
  std::vector<Case> cases = {{"", "measured"}};
  if (e2e::ocio_version() >= "2.5") cases.push_back({"ocio://studio-config-latest", "config"});
  for (const Case& c : cases) {
    SCOPED_TRACE(c.config);
    const std::string cfg = c.config.empty() ? "" : " --config " + c.config;
    fs::remove_all(s / "dst");
    // The image command's report.
    e2e::Run r = run(png + " -o " + (s / "a.exr") + " --report " + (s / "a.json") + cfg + " -q");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    expect_identity(Json::parse(e2e::slurp(s / "a.json")), "srgb_rec709_scene", c.source,
                    "sdr-video");
    // The manifest: converted, then up to date (read back from the output's header).
    fs::create_directories(s / "lib");
    fs::copy_file(png, s / "lib/albedo.png", fs::copy_options::overwrite_existing);
    for (const char* status : {"converted", "up_to_date"}) {
      SCOPED_TRACE(status);
      ASSERT_EQ(run("ingest " + (s / "lib") + " -o " + (s / "dst") + cfg + " -q").exit_code, 0);
      const std::string manifest = e2e::slurp(s / "dst/spectralize-ingest.jsonl");
      const Json record = Json::parse(manifest.substr(0, manifest.find('\n')));
      EXPECT_EQ(record.at("status"), status);
      expect_identity(record, "srgb_rec709_scene", c.source, "sdr-video");
    }
    // --to-rgb's report: the space written.
    r = run("--to-rgb " + (s / "a.exr") + " -o " + (s / "b.png") + " --report " + (s / "b.json") +
            cfg + " -q");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    expect_identity(Json::parse(e2e::slurp(s / "b.json")), "srgb_rec709_scene", c.source,
                    "sdr-video");
  }
  // --color's JSON; a log space no interop ID names: null, its encoding the config's.
  const Json log = Json::parse(run("--color 0.4,0.4,0.4 --format json --colorspace ACEScct").out);
  expect_identity(log, nullptr, nullptr, "log");
  const Json cg = Json::parse(run("--color 0.4,0.4,0.4 --format json --colorspace ACEScg").out);
  expect_identity(cg, "lin_ap1_scene", "measured", "scene-linear");
  // An interop ID names the space that has it, as OpenUSD and OIIO 3 name spaces.
  const Json by_id =
      Json::parse(run("--color 0.4,0.4,0.4 --format json --colorspace lin_ap1_scene").out);
  EXPECT_EQ(by_id.at("colorspace"), "ACEScg");
  EXPECT_EQ(by_id.at("xyz"), cg.at("xyz"));
}

}  // namespace
