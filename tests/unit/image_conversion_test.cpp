// One RGB image to one spectral image (pipeline/image_conversion.h, docs/DESIGN.md §10), on
// tiny images held in memory and plans made as a front end makes them (plan_to_spectral, then
// planned_input): the bands of every pixel integrate back to its colour (emission: its XYZ;
// reflectance: its XYZ white-balanced, within [0, 1]; docs/DESIGN.md §3) whatever the order of
// the input's channels, the previews are the colour again, alpha passes through (straight alpha
// premultiplied into light), every pixel is counted and its trouble warned about as the caller
// spells options; the header records why the space and mode were chosen, the warnings known
// before the pixels and room for the counts, which recorded_warnings words again; the node
// cache is loaded and saved when asked, or left to a shared pool. Oracles: the reference
// integration and the Rec.709 matrix of tests/unit/test_support.h, and the pixels each case
// makes.

#include "pipeline/image_conversion.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "file_test_support.h"
#include "spectralize/core/error.h"
#include "test_support.h"

namespace fs = std::filesystem;

namespace spectralize {
namespace {

const std::string kRec709 = "Linear Rec.709 (sRGB)";
const OptionNames kFlags{"--", "-o"};
const OptionNames kKeywords{"", "output"};
const LogFn kQuiet = [](int, const std::string&) {};

// Float samples and OCIO's float maths (docs/DESIGN.md §3: float files, 1e-5).
constexpr double kFloatTolerance = 1e-5;
// A colour through OCIO's float matrices twice (to XYZ, and the previews back to RGB).
constexpr double kTwiceThroughOcio = 1e-4;

Settings settings_of(ModeChoice mode, const std::string& space = kRec709) {
  Settings s;
  s.colorspace = space;
  s.preview_colorspace = kRec709;
  s.mode = mode;
  s.half = false;
  s.threads = 2;
  return s;
}

// The plan of input `input` with these channels, as a front end makes it.
JobPlan plan_of(const Settings& s, const OIIO::ImageSpec& spec, const OptionNames& names = kFlags,
                const std::string& input = "in.exr") {
  return planned_input(plan_to_spectral(s, "out.exr", names), input, spec);
}

OIIO::ImageSpec rgba_spec(int w, int h) {
  OIIO::ImageSpec spec = test::spec_of({"R", "G", "B", "A"}, OIIO::TypeFloat, w, h);
  spec.alpha_channel = 3;
  return spec;
}

std::vector<float> packed(const std::vector<std::array<float, 3>>& colours) {
  std::vector<float> v;
  for (const auto& c : colours) v.insert(v.end(), c.begin(), c.end());
  return v;
}

// The output of one conversion: the pixels and where things are.
struct Converted {
  OIIO::ImageSpec spec;
  std::vector<float> px;
  int channel(const std::string& name) const { return spec.channelindex(name); }
  float at(std::size_t pixel, int c) const {
    return px[pixel * static_cast<std::size_t>(spec.nchannels) + static_cast<std::size_t>(c)];
  }
  // The bands of a pixel: every channel after the previews (and alpha), by the layout's names.
  std::vector<double> bands(std::size_t pixel) const {
    std::vector<double> v;
    for (int c = 0; c < spec.nchannels; ++c) {
      const std::string& n = spec.channelnames[c];
      if (n.rfind("S0.", 0) == 0 || n.rfind("T.", 0) == 0) v.push_back(at(pixel, c));
    }
    return v;
  }
};

Converted run(ImageConversion& conversion, const std::vector<float>& in, std::size_t n) {
  Converted c;
  c.spec = conversion.output_spec();
  c.px.assign(n * static_cast<std::size_t>(c.spec.nchannels), -999.0f);
  conversion.convert(in.data(), n, c.px.data());
  return c;
}

Xyz integrated(const Settings& s, const std::vector<double>& values) {
  return test::reference_xyz(s.spectral, values);
}

Xyz balance(const Settings& s) {
  return test::white_balance(s.spectral);
}

Xyz rec709(const std::array<float, 3>& c) {
  return test::rgb(test::kRec709ToXyz, c[0], c[1], c[2]);
}

bool any_has(const std::vector<std::string>& lines, const std::string& part) {
  return std::any_of(lines.begin(), lines.end(),
                     [&](const std::string& l) { return l.find(part) != std::string::npos; });
}

// SOURCE_DATE_EPOCH set for one scope, restored after.
struct SourceDateEpoch {
  std::optional<std::string> saved;
  explicit SourceDateEpoch(const char* value) {
    if (const char* v = std::getenv("SOURCE_DATE_EPOCH")) saved = v;
    ::setenv("SOURCE_DATE_EPOCH", value, 1);
  }
  ~SourceDateEpoch() {
    if (saved)
      ::setenv("SOURCE_DATE_EPOCH", saved->c_str(), 1);
    else
      ::unsetenv("SOURCE_DATE_EPOCH");
  }
};

const std::vector<std::array<float, 3>> kLights = {
    {1, 1, 1},    {0.18f, 0.18f, 0.18f}, {0.8f, 0.2f, 0.1f}, {0.05f, 0.6f, 0.3f},
    {40, 30, 20}, {0.3f, 0.3f, 0.9f},    {2, 0.5f, 0.25f},   {0.01f, 0.02f, 0.03f}};

// --- Pixels ---

TEST(ImageConversion, EmissionBandsIntegrateBackToThePixelsAndThePreviewsAreThePixels) {
  const OIIO::ImageSpec spec = test::spec_of({"R", "G", "B"}, OIIO::TypeFloat, 4, 2);
  ImageConversion conversion(plan_of(settings_of(ModeChoice::emission), spec), spec, "openexr",
                             false, kQuiet);
  const Converted out = run(conversion, packed(kLights), 8);
  ASSERT_EQ(out.spec.nchannels, 3 + 81);
  EXPECT_EQ(out.spec.width, 4);
  EXPECT_EQ(out.spec.height, 2);
  EXPECT_EQ(out.spec.format, OIIO::TypeFloat);
  const Settings& s = conversion.report().settings;
  for (std::size_t p = 0; p < kLights.size(); ++p) {
    SCOPED_TRACE(p);
    const std::vector<double> b = out.bands(p);
    ASSERT_EQ(b.size(), 81u);
    EXPECT_LT(test::rel_err(integrated(s, b), rec709(kLights[p])), kFloatTolerance);
    const float peak = *std::max_element(kLights[p].begin(), kLights[p].end());
    for (int k = 0; k < 3; ++k)
      EXPECT_LT(std::abs(out.at(p, out.channel(std::string(1, "RGB"[k]))) - kLights[p][k]) / peak,
                kTwiceThroughOcio);
  }
  const ImageReport& rep = conversion.finish(kQuiet);
  EXPECT_EQ(rep.input, "in.exr");
  EXPECT_EQ(rep.input_format, "openexr");
  EXPECT_EQ(rep.width, 4);
  EXPECT_EQ(rep.height, 2);
  EXPECT_EQ(rep.pixels, 8u);
  EXPECT_EQ(rep.bands, 81);
  EXPECT_EQ(rep.colorspace, kRec709);
  EXPECT_EQ(rep.preview_colorspace, kRec709);
  EXPECT_EQ(rep.settings.spectral.mode, Mode::emission);
  EXPECT_FALSE(rep.alpha);
  EXPECT_EQ(rep.counts.error_pixels, 8u);
  EXPECT_LT(rep.counts.max_error, kFloatTolerance);
  EXPECT_TRUE(rep.warnings.empty()) << ::testing::PrintToString(rep.warnings);
}

TEST(ImageConversion, ReflectancesAreBoundedAndTheInputsChannelOrderIsFollowed) {
  const std::vector<std::array<float, 3>> paints = {
      {0.9f, 0.9f, 0.9f}, {0.5f, 0.2f, 0.1f}, {0.05f, 0.4f, 0.2f}, {0.1f, 0.1f, 0.6f}};
  const OIIO::ImageSpec rgb = test::spec_of({"R", "G", "B"}, OIIO::TypeFloat, 2, 2);
  const OIIO::ImageSpec bgr = test::spec_of({"B", "G", "R"}, OIIO::TypeFloat, 2, 2);
  const Settings s = settings_of(ModeChoice::reflectance);
  ImageConversion a(plan_of(s, rgb), rgb, "openexr", false, kQuiet);
  ImageConversion b(plan_of(s, bgr), bgr, "openexr", false, kQuiet);
  std::vector<float> reversed;
  for (const auto& c : paints) reversed.insert(reversed.end(), {c[2], c[1], c[0]});
  const Converted ra = run(a, packed(paints), 4), rb = run(b, reversed, 4);
  const Xyz w = balance(a.report().settings);
  for (std::size_t p = 0; p < paints.size(); ++p) {
    SCOPED_TRACE(p);
    const std::vector<double> v = ra.bands(p);
    for (double x : v) {
      EXPECT_GE(x, 0.0);
      EXPECT_LE(x, 1.0);
    }
    const Xyz lin = rec709(paints[p]);
    EXPECT_LT(test::rel_err(integrated(a.report().settings, v),
                            Xyz{lin.X * w.X, lin.Y * w.Y, lin.Z * w.Z}),
              kFloatTolerance);
    EXPECT_EQ(rb.bands(p), v);  // B, G, R: the same colour, the same spectrum
  }
  EXPECT_EQ(a.report().settings.spectral.mode, Mode::reflectance);
}

TEST(ImageConversion, AlphaPassesThroughAndStraightAlphaIsPremultipliedIntoLight) {
  const OIIO::ImageSpec spec = rgba_spec(2, 1);
  const std::vector<float> in = {0.6f, 0.3f, 0.2f, 0.5f, 0.2f, 0.4f, 0.1f, 0.25f};
  const Settings s = settings_of(ModeChoice::emission);
  ImageConversion associated(plan_of(s, spec), spec, "openexr", false, kQuiet);
  ImageConversion straight(plan_of(s, spec), spec, "openexr", true, kQuiet);
  const Converted oa = run(associated, in, 2), os = run(straight, in, 2);
  ASSERT_EQ(oa.spec.nchannels, 4 + 81);
  ASSERT_EQ(oa.channel("A"), 3);
  EXPECT_EQ(oa.spec.alpha_channel, 3);
  for (std::size_t p = 0; p < 2; ++p) {
    SCOPED_TRACE(p);
    const float alpha = in[4 * p + 3];
    const std::array<float, 3> c = {in[4 * p], in[4 * p + 1], in[4 * p + 2]};
    EXPECT_EQ(oa.at(p, 3), alpha);
    EXPECT_EQ(os.at(p, 3), alpha);
    // Associated: the colour as given; straight: times alpha (docs/DESIGN.md §9).
    EXPECT_LT(test::rel_err(integrated(associated.report().settings, oa.bands(p)), rec709(c)),
              kFloatTolerance);
    EXPECT_LT(test::rel_err(integrated(straight.report().settings, os.bands(p)), alpha * rec709(c)),
              kFloatTolerance);
  }
  EXPECT_TRUE(associated.report().alpha);
  EXPECT_FALSE(associated.report().straight_alpha);
  EXPECT_TRUE(straight.report().straight_alpha);
}

// --- Counts and warnings ---

TEST(ImageConversion, BadPixelsAreCountedAndWarnedAboutAsTheCallerSpellsOptions) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const OIIO::ImageSpec spec = test::spec_of({"R", "G", "B"}, OIIO::TypeFloat, 3, 1);
  const std::vector<float> in = {nan, 0.5f, 0.5f, 2, 2, 2, 0.3f, 0.3f, 0.3f};
  for (const OptionNames& names : {kFlags, kKeywords}) {
    SCOPED_TRACE(names.prefix);
    ImageConversion conversion(
        plan_of(settings_of(ModeChoice::reflectance), spec, names, "bad.exr"), spec, "openexr",
        false, kQuiet);
    run(conversion, in, 3);
    std::vector<std::string> logged;
    const ImageReport& rep = conversion.finish([&](int level, const std::string& m) {
      if (level == 0) logged.push_back(m);
    });
    EXPECT_EQ(rep.counts.invalid, 1u);
    EXPECT_EQ(rep.counts.brighter_than_white, 1u);
    EXPECT_EQ(rep.counts.error_pixels, 2u);
    EXPECT_TRUE(any_has(rep.warnings, "'bad.exr': 1 pixels are NaN or infinite"))
        << ::testing::PrintToString(rep.warnings);
    EXPECT_TRUE(any_has(rep.warnings, "'bad.exr': 1 pixels are brighter than a white surface"))
        << ::testing::PrintToString(rep.warnings);
    EXPECT_TRUE(any_has(rep.warnings, " " + names("mode") + " emission"))
        << ::testing::PrintToString(rep.warnings);
    EXPECT_EQ(logged, rep.warnings);  // said as reported
  }
}

// --- The header ---

TEST(ImageConversion, TheHeaderSaysWhyAndRecordsTheWarningsKnownBeforeThePixels) {
  // A Z channel is ignored with a warning: known before any pixel.
  const OIIO::ImageSpec spec = test::spec_of({"R", "G", "B", "Z"}, OIIO::TypeFloat, 2, 1);
  const JobPlan plan = plan_of(settings_of(ModeChoice::emission), spec);
  ASSERT_FALSE(plan.interpretation.warnings.empty());
  ConversionContext context;
  context.record_in_header = true;
  context.attributes = [](const Settings& resolved) {
    return std::map<std::string, std::string>{
        {"spectralize:modeReason", "the caller's"},
        {"custom:mode", std::string(to_string(resolved.spectral.mode == Mode::emission
                                                  ? ModeChoice::emission
                                                  : ModeChoice::reflectance))}};
  };
  std::vector<std::string> logged;
  SourceDateEpoch epoch("0");
  ImageConversion conversion(
      plan, spec, "openexr", false,
      [&](int level, const std::string& m) {
        if (level == 0) logged.push_back(m);
      },
      context);
  const OIIO::ImageSpec& out = conversion.output_spec();
  EXPECT_EQ(out.get_string_attribute("spectralize:colorspaceReason"),
            plan.interpretation.colorspace_reason);
  EXPECT_EQ(out.get_string_attribute("spectralize:modeReason"), "the caller's");  // theirs wins
  EXPECT_EQ(out.get_string_attribute("custom:mode"), "emission");  // made from the resolved
  EXPECT_EQ(out.get_string_attribute("DateTime"), "1970:01:01 00:00:00");
  const auto warnings = nlohmann::json::parse(out.get_string_attribute(kWarningsAttribute))
                            .get<std::vector<std::string>>();
  EXPECT_EQ(warnings, plan.interpretation.warnings);
  EXPECT_EQ(conversion.report().warnings, plan.interpretation.warnings);
  EXPECT_EQ(logged, plan.interpretation.warnings);
  // Room for the counts, zero until the job fills them in.
  for (const char* name :
       {"invalidPixels", "invalidAlphaPixels", "negativeLuminancePixels", "outsideLocusPixels",
        "outsideSolidPixels", "brighterThanWhitePixels", "halfOverflowPixels"}) {
    double v = -1;
    EXPECT_TRUE(out.getattribute(std::string("spectralize:") + name, OIIO::TypeDesc::DOUBLE, &v))
        << name;
    EXPECT_EQ(v, 0.0) << name;
  }
  // Without record_in_header, neither.
  ImageConversion plain(plan, spec, "openexr", false, kQuiet);
  EXPECT_EQ(plain.output_spec().find_attribute(kWarningsAttribute), nullptr);
  EXPECT_EQ(plain.output_spec().find_attribute("spectralize:invalidPixels"), nullptr);
}

TEST(ImageConversion, AnUnusableSourceDateEpochIsAWarningOfTheConversion) {
  const OIIO::ImageSpec spec = test::spec_of({"R", "G", "B"}, OIIO::TypeFloat, 1, 1);
  SourceDateEpoch epoch("yesterday");
  ImageConversion conversion(plan_of(settings_of(ModeChoice::emission), spec), spec, "openexr",
                             false, kQuiet);
  EXPECT_TRUE(any_has(conversion.report().warnings, "SOURCE_DATE_EPOCH"))
      << ::testing::PrintToString(conversion.report().warnings);
}

TEST(ImageConversion, RecordedWarningsAreTheHeadersThenItsCountsWordedAgain) {
  PixelCounts c;
  c.invalid = 3;
  c.half_overflow = 2;
  std::map<std::string, double> doubles;
  for (const auto& [name, value] : count_attributes(c)) doubles["spectralize:" + name] = value;
  const std::map<std::string, std::string> strings = {
      {kWarningsAttribute, R"(["before one", "before two"])"}};
  std::vector<std::string> want = {"before one", "before two"};
  for (const std::string& w : count_warnings(c, "'in.exr'", "pixels", kKeywords)) want.push_back(w);
  EXPECT_EQ(recorded_warnings(strings, doubles, "in.exr", kKeywords), want);
  // A record that is not a JSON array of strings adds nothing of its own.
  want.erase(want.begin(), want.begin() + 2);
  for (const char* bad : {"not json", "{\"a\": 1}", "[1, 2]"})
    EXPECT_EQ(recorded_warnings({{kWarningsAttribute, bad}}, doubles, "in.exr", kKeywords), want)
        << bad;
  EXPECT_TRUE(recorded_warnings({}, {}, "in.exr", kKeywords).empty());
}

// --- The node cache ---

TEST(ImageConversion, TheCacheIsLoadedAndSavedWhenAskedAndNotWhenTheReaderSaysNo) {
  test::TempDir t("image_conversion");
  const OIIO::ImageSpec spec = test::spec_of({"R", "G", "B"}, OIIO::TypeFloat, 4, 2);
  Settings s = settings_of(ModeChoice::emission);
  s.cache_dir = t / "cache";
  std::string file;
  {
    ImageConversion reader(plan_of(s, spec), spec, "openexr", false, kQuiet);
    EXPECT_EQ(reader.report().cache_status, "new");
    file = reader.report().cache_file;
    EXPECT_EQ(fs::path(file).parent_path(), fs::path(s.cache_dir));
    run(reader, packed(kLights), 8);
    reader.finish(kQuiet, false);
    EXPECT_FALSE(fs::exists(file));  // a reader not asked to write writes nothing
  }
  std::uint64_t computed = 0;
  {
    ImageConversion first(plan_of(s, spec), spec, "openexr", false, kQuiet);
    run(first, packed(kLights), 8);
    computed = first.finish(kQuiet).cache.nodes_computed;
    EXPECT_GT(computed, 0u);
    EXPECT_TRUE(fs::exists(file));
  }
  ImageConversion second(plan_of(s, spec), spec, "openexr", false, kQuiet);
  EXPECT_EQ(second.report().cache_status, "loaded");
  EXPECT_EQ(second.report().cache_file, file);
  run(second, packed(kLights), 8);
  const ImageReport& rep = second.finish(kQuiet);
  EXPECT_EQ(rep.cache.nodes_loaded, computed);
  EXPECT_EQ(rep.cache.nodes_computed, 0u);
}

TEST(ImageConversion, ACacheFolderThatCannotBeMadeIsAWarningInTheCallersSpelling) {
  test::TempDir t("image_conversion");
  std::ofstream(t / "file") << "x";
  const OIIO::ImageSpec spec = test::spec_of({"R", "G", "B"}, OIIO::TypeFloat, 1, 1);
  Settings s = settings_of(ModeChoice::emission);
  s.cache_dir = t / "file";
  for (const OptionNames& names : {kFlags, kKeywords}) {
    SCOPED_TRACE(names.prefix);
    ImageConversion conversion(plan_of(s, spec, names), spec, "openexr", false, kQuiet);
    EXPECT_TRUE(conversion.report().cache_file.empty());
    EXPECT_TRUE(any_has(conversion.report().warnings, names("cache") + " '" + s.cache_dir + "'"))
        << ::testing::PrintToString(conversion.report().warnings);
    if (names.prefix.empty()) {
      EXPECT_FALSE(any_has(conversion.report().warnings, "--"));
    }
  }
}

TEST(ImageConversion, ConversionsSharingAPoolShareItsTableAndLeaveTheSavingToIt) {
  test::TempDir t("image_conversion");
  const OIIO::ImageSpec spec = test::spec_of({"R", "G", "B"}, OIIO::TypeFloat, 4, 2);
  Settings s = settings_of(ModeChoice::emission);
  s.cache_dir = t.dir.string();
  TablePool pool;
  ConversionContext context;
  context.pool = &pool;
  ImageConversion first(plan_of(s, spec), spec, "openexr", false, kQuiet, context);
  run(first, packed(kLights), 8);
  const std::uint64_t computed = first.finish(kQuiet).cache.nodes_computed;
  EXPECT_GT(computed, 0u);
  EXPECT_EQ(first.report().cache_status, "new");
  EXPECT_TRUE(fs::is_empty(t.dir));  // the pool saves, at the end of the batch
  ImageConversion second(plan_of(s, spec), spec, "openexr", false, kQuiet, context);
  EXPECT_EQ(second.report().cache_file, first.report().cache_file);
  run(second, packed(kLights), 8);
  EXPECT_EQ(second.finish(kQuiet).cache.nodes_computed, computed);  // nothing solved again
  EXPECT_TRUE(pool.save().empty());
  EXPECT_TRUE(fs::exists(first.report().cache_file));
}

TEST(ImageConversion, APoolsUnusableCacheFolderIsSaidInTheCallersSpellingToo) {
  test::TempDir t("image_conversion");
  std::ofstream(t / "file") << "x";
  const OIIO::ImageSpec spec = test::spec_of({"R", "G", "B"}, OIIO::TypeFloat, 1, 1);
  Settings s = settings_of(ModeChoice::emission);
  s.cache_dir = t / "file";
  for (const OptionNames& names : {kFlags, kKeywords}) {
    SCOPED_TRACE(names.prefix);
    TablePool pool;
    ConversionContext context;
    context.pool = &pool;
    std::vector<std::string> logged;
    ImageConversion conversion(
        plan_of(s, spec, names), spec, "openexr", false,
        [&](int level, const std::string& m) {
          if (level == 0) logged.push_back(m);
        },
        context);
    EXPECT_TRUE(conversion.report().cache_file.empty());
    ASSERT_EQ(logged.size(), 1u) << ::testing::PrintToString(logged);
    EXPECT_EQ(logged[0].rfind(names("cache") + " '" + s.cache_dir + "'", 0), 0u) << logged[0];
  }
}

// --- Refusals ---

TEST(ImageConversion, APlanNotDecidedForAnRgbInputIsRefused) {
  const OIIO::ImageSpec spec = test::spec_of({"R", "G", "B"}, OIIO::TypeFloat, 1, 1);
  const JobPlan undecided = plan_to_spectral(settings_of(ModeChoice::emission), "out.exr", kFlags);
  EXPECT_THROW(ImageConversion(undecided, spec, "openexr", false, kQuiet), Error);
  const OIIO::ImageSpec spectral = test::spec_of({"S0.500nm", "S0.600nm"}, OIIO::TypeFloat, 1, 1);
  const JobPlan to_rgb =
      planned_input(plan_to_rgb(Settings{}, "out.exr", false, false, kFlags), "in.exr", spectral);
  EXPECT_THROW(ImageConversion(to_rgb, spectral, "openexr", false, kQuiet), Error);
}

}  // namespace
}  // namespace spectralize
