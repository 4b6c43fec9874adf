// What a conversion reports (pipeline/image_report.h): count_warnings says one warning per kind
// of trouble the counts show, each starting with its subject, counting its noun and naming
// options as the caller spells them ("--mode" on the command line, "mode" in Python); the
// counts a header records come back from its attributes, absent or unusable ones as 0, exactly
// up to 2^53; report_json holds every field of the report under its key (the settings by the
// schema's keys and canonical texts, docs/DESIGN.md §8; paths not valid UTF-8 escaped and
// base64'd, §9). Oracles: the counts each case sets, sums and means computed here, and the JSON
// parsed back with nlohmann.

#include "pipeline/image_report.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <map>
#include <string>
#include <vector>

namespace spectralize {
namespace {

const OptionNames kFlags{"--", "-o"};
const OptionNames kKeywords{"", "output"};

// Counts with a distinct number for every field.
PixelCounts distinct_counts() {
  PixelCounts c;
  c.invalid = 2;
  c.negative = 3;
  c.outside_locus = 5;
  c.outside_solid = 7;
  c.brighter_than_white = 11;
  c.negative_component = 13;
  c.black = 17;
  c.half_overflow = 19;
  c.alpha_invalid = 23;
  c.error_pixels = 4;
  c.max_error = 3e-6;
  c.sum_error = 8e-6;
  return c;
}

bool starts_with(const std::string& s, const std::string& prefix) {
  return s.rfind(prefix, 0) == 0;
}

bool has(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

// --- count_warnings ---

TEST(ImageReport, CleanCountsGiveNoWarnings) {
  PixelCounts c;
  c.black = 40;               // black and negative components are information, not trouble
  c.negative_component = 12;  // (a negative component is still a colour)
  c.error_pixels = 60;
  c.max_error = 1e-6;
  EXPECT_TRUE(count_warnings(PixelCounts{}, "'a.exr'", "pixels", kFlags).empty());
  EXPECT_TRUE(count_warnings(c, "'a.exr'", "pixels", kFlags).empty());
}

TEST(ImageReport, EachKindOfTroubleIsOneWarningInOrderCountingItsNoun) {
  const std::vector<std::string> w =
      count_warnings(distinct_counts(), "'albedo.png'", "colours", kFlags);
  ASSERT_EQ(w.size(), 5u) << ::testing::PrintToString(w);
  for (const std::string& line : w) EXPECT_TRUE(starts_with(line, "'albedo.png': ")) << line;
  // NaN or infinite colours, bad alpha, out of gamut, brighter than white, HALF overflow.
  EXPECT_TRUE(starts_with(w[0], "'albedo.png': 2 colours are NaN or infinite")) << w[0];
  EXPECT_TRUE(starts_with(w[1], "'albedo.png': 23 colours have an alpha")) << w[1];
  // Out of gamut: the three kinds together, 3 + 5 + 7, and each.
  EXPECT_TRUE(starts_with(w[2], "'albedo.png': 15 colours out of gamut")) << w[2];
  EXPECT_TRUE(has(w[2], "3 negative luminance")) << w[2];
  EXPECT_TRUE(has(w[2], "5 outside the spectral locus")) << w[2];
  EXPECT_TRUE(has(w[2], "7 outside the reflectance solid")) << w[2];
  EXPECT_TRUE(starts_with(w[3], "'albedo.png': 11 colours are brighter than a white surface"))
      << w[3];
  EXPECT_TRUE(starts_with(w[4], "'albedo.png': 19 colours have samples above HALF's maximum"))
      << w[4];
}

TEST(ImageReport, EveryCountAloneGivesItsOwnWarning) {
  using Count = std::uint64_t PixelCounts::*;
  const Count fields[] = {&PixelCounts::invalid,
                          &PixelCounts::alpha_invalid,
                          &PixelCounts::negative,
                          &PixelCounts::outside_locus,
                          &PixelCounts::outside_solid,
                          &PixelCounts::half_overflow,
                          &PixelCounts::brighter_than_white};
  for (auto field : fields) {
    PixelCounts c;
    c.*field = 1;
    const std::vector<std::string> w = count_warnings(c, "rgb", "pixels", kFlags);
    ASSERT_EQ(w.size(), 1u) << ::testing::PrintToString(w);
    EXPECT_TRUE(starts_with(w[0], "rgb: 1 pixels")) << w[0];
  }
}

TEST(ImageReport, WarningsSpellOptionsAsTheCallerDoes) {
  PixelCounts c;
  c.brighter_than_white = 1;
  c.half_overflow = 1;
  auto joined = [&](const OptionNames& names) {
    std::string all;
    for (const std::string& w : count_warnings(c, "rgb", "pixels", names)) all += w + "\n";
    return all;
  };
  const std::string cli = joined(kFlags), python = joined(kKeywords);
  EXPECT_TRUE(has(cli, "--mode emission")) << cli;
  EXPECT_TRUE(has(cli, "use --format float")) << cli;
  EXPECT_TRUE(has(python, " mode emission")) << python;
  EXPECT_TRUE(has(python, "use format float")) << python;
  EXPECT_FALSE(has(python, "--")) << python;
}

// --- The counts in a header ---

std::map<std::string, double> as_header(const std::vector<std::pair<std::string, double>>& a) {
  std::map<std::string, double> header;
  for (const auto& [name, value] : a) header["spectralize:" + name] = value;
  return header;
}

TEST(ImageReport, TheRecordedCountsComeBackFromTheHeader) {
  const PixelCounts c = distinct_counts();
  const auto attributes = count_attributes(c);
  std::map<std::string, int> names;
  for (const auto& [name, value] : attributes) ++names[name];
  EXPECT_EQ(names.size(), attributes.size());  // no name twice
  const PixelCounts back = counts_from_attributes(as_header(attributes));
  EXPECT_EQ(back.invalid, c.invalid);
  EXPECT_EQ(back.alpha_invalid, c.alpha_invalid);
  EXPECT_EQ(back.negative, c.negative);
  EXPECT_EQ(back.outside_locus, c.outside_locus);
  EXPECT_EQ(back.outside_solid, c.outside_solid);
  EXPECT_EQ(back.brighter_than_white, c.brighter_than_white);
  EXPECT_EQ(back.half_overflow, c.half_overflow);
  // Exactly the counts count_warnings speaks of: a later reader words the same warnings.
  EXPECT_EQ(count_warnings(back, "'a.exr'", "pixels", kFlags),
            count_warnings(c, "'a.exr'", "pixels", kFlags));
  // What no warning speaks of is not recorded.
  EXPECT_EQ(back.black, 0u);
  EXPECT_EQ(back.negative_component, 0u);
  EXPECT_EQ(back.error_pixels, 0u);
}

TEST(ImageReport, RecordedCountsAreExactUpTo2To53) {
  PixelCounts c;
  c.invalid = (std::uint64_t{1} << 53) - 1;
  c.half_overflow = std::uint64_t{1} << 40;
  const PixelCounts back = counts_from_attributes(as_header(count_attributes(c)));
  EXPECT_EQ(back.invalid, c.invalid);
  EXPECT_EQ(back.half_overflow, c.half_overflow);
}

TEST(ImageReport, AbsentOrUnusableRecordedCountsAreZero) {
  std::map<std::string, double> header = as_header(count_attributes(distinct_counts()));
  header.erase("spectralize:invalidPixels");
  header["spectralize:negativeLuminancePixels"] = -4;
  header["spectralize:outsideLocusPixels"] = std::nan("");
  header["invalidAlphaPixels"] = 9;  // without the prefix: not spectralize's
  const PixelCounts back = counts_from_attributes(header);
  EXPECT_EQ(back.invalid, 0u);
  EXPECT_EQ(back.negative, 0u);
  EXPECT_EQ(back.outside_locus, 0u);
  EXPECT_EQ(back.alpha_invalid, 23u);  // the prefixed one
  EXPECT_EQ(back.outside_solid, 7u);
  const PixelCounts none = counts_from_attributes({});
  EXPECT_TRUE(count_warnings(none, "rgb", "pixels", kFlags).empty());
}

// --- report_json ---

ImageReport full_report() {
  ImageReport r;
  r.input = "in/albedo.png";
  r.output = "out/albedo.exr";
  r.input_format = "png";
  r.width = 640, r.height = 480, r.bands = 31;
  r.mip_levels = 3, r.subimages = 2;
  r.tiled_input = true;
  r.colorspace = "sRGB - Texture";
  r.colorspace_reason = "8-bit PNG";
  r.mode_reason = "'albedo' names a surface";
  r.preview_colorspace = "Linear Rec.709 (sRGB)";
  r.settings.colorspace = "ACEScg";  // not what the job chose: the report's own wins
  r.settings.mode = ModeChoice::automatic;
  r.settings.spectral.mode = Mode::reflectance;
  r.settings.spectral.grid = WavelengthGrid(400, 700, 10);
  r.settings.spectral.illuminant = "D50";
  r.alpha = true, r.straight_alpha = true;
  r.pixels = 640 * 480;
  r.counts = distinct_counts();
  r.cache.nodes_computed = 101;
  r.cache.nodes_loaded = 202;
  r.cache.nodes_infeasible = 303;
  r.cache.fallback_solves = 404;
  r.cache.fallback_hits = 505;
  r.cache_file = "/tmp/cache/spectralize-table-0123456789abcdef.bin";
  r.cache_status = "loaded";
  r.warnings = {"first", "second"};
  r.seconds_setup = 0.25, r.seconds_convert = 1.5, r.seconds_write = 0.75, r.seconds_total = 2.5;
  return r;
}

TEST(ImageReport, TheJsonHoldsEveryFieldOfTheReport) {
  const ImageReport r = full_report();
  const nlohmann::json j = nlohmann::json::parse(report_json(r));
  EXPECT_EQ(j.at("input"), r.input);
  EXPECT_EQ(j.at("output"), r.output);
  EXPECT_FALSE(j.contains("input_base64"));  // valid UTF-8 is written as it is
  EXPECT_EQ(j.at("input_format"), "png");
  EXPECT_EQ(j.at("width"), 640);
  EXPECT_EQ(j.at("height"), 480);
  EXPECT_EQ(j.at("bands"), 31);
  EXPECT_EQ(j.at("input_mip_levels"), 3);
  EXPECT_EQ(j.at("input_subimages"), 2);
  EXPECT_EQ(j.at("input_tiled"), true);
  EXPECT_EQ(j.at("colorspace"), "sRGB - Texture");
  EXPECT_EQ(j.at("colorspace_reason"), "8-bit PNG");
  EXPECT_EQ(j.at("mode_reason"), r.mode_reason);
  EXPECT_EQ(j.at("preview_colorspace"), "Linear Rec.709 (sRGB)");
  // The settings by the schema's keys, the mode as done (not "auto").
  EXPECT_EQ(j.at("mode"), "reflectance");
  EXPECT_EQ(j.at("wavelengths"), "400:700:10");
  EXPECT_EQ(j.at("illuminant"), "D50");
  EXPECT_EQ(j.at("alpha"), true);
  EXPECT_EQ(j.at("alpha_straight_in_input"), true);
  EXPECT_EQ(j.at("pixels"), 640 * 480);
  EXPECT_EQ(j.at("out_of_gamut_pixels"), 3 + 5 + 7);
  const nlohmann::json& g = j.at("out_of_gamut");
  EXPECT_EQ(g.at("negative_luminance"), 3);
  EXPECT_EQ(g.at("outside_locus"), 5);
  EXPECT_EQ(g.at("outside_reflectance_solid"), 7);
  EXPECT_EQ(g.at("brighter_than_white"), 11);
  EXPECT_EQ(j.at("invalid_pixels"), 2);
  EXPECT_EQ(j.at("invalid_alpha_pixels"), 23);
  EXPECT_EQ(j.at("negative_component_pixels"), 13);
  EXPECT_EQ(j.at("black_pixels"), 17);
  EXPECT_EQ(j.at("half_overflow_pixels"), 19);
  EXPECT_EQ(j.at("max_relative_xyz_error").get<double>(), 3e-6);
  EXPECT_DOUBLE_EQ(j.at("mean_relative_xyz_error").get<double>(), 8e-6 / 4);
  const nlohmann::json& cache = j.at("cache");
  EXPECT_EQ(cache.at("nodes_computed"), 101);
  EXPECT_EQ(cache.at("nodes_reused"), 202);
  EXPECT_EQ(cache.at("nodes_infeasible"), 303);
  EXPECT_EQ(cache.at("fallbacks"), 404);
  EXPECT_EQ(cache.at("fallback_hits"), 505);
  EXPECT_EQ(cache.at("file"), r.cache_file);
  EXPECT_EQ(cache.at("status"), "loaded");
  EXPECT_EQ(j.at("warnings"), (std::vector<std::string>{"first", "second"}));
  const nlohmann::json& s = j.at("seconds");
  EXPECT_EQ(s.at("setup"), 0.25);
  EXPECT_EQ(s.at("convert"), 1.5);
  EXPECT_EQ(s.at("write"), 0.75);
  EXPECT_EQ(s.at("total"), 2.5);
}

TEST(ImageReport, TheJsonLeavesOutWhatDidNotHappen) {
  ImageReport r = full_report();
  r.alpha = false;
  r.cache_file.clear();
  r.counts.error_pixels = 0;  // nothing measured: a mean of 0, not NaN
  r.counts.sum_error = 0;
  const nlohmann::json j = nlohmann::json::parse(report_json(r));
  EXPECT_EQ(j.at("alpha"), false);
  EXPECT_FALSE(j.contains("alpha_straight_in_input"));
  EXPECT_FALSE(j.at("cache").contains("file"));
  EXPECT_FALSE(j.at("cache").contains("status"));
  EXPECT_EQ(j.at("mean_relative_xyz_error"), 0.0);
  // Settings that do not matter for these settings are not reported (a filter is the paper
  // model's; an illuminant a reflectance's).
  r.settings.spectral.mode = Mode::emission;
  EXPECT_FALSE(nlohmann::json::parse(report_json(r)).contains("illuminant"));
}

TEST(ImageReport, OneLineWhenAskedAndNamesThatAreNotUtf8AreKeptLosslessly) {
  ImageReport r = full_report();
  r.input = "in/\xff.png";
  const std::string line = report_json(r, -1);
  EXPECT_EQ(line.find('\n'), std::string::npos);
  EXPECT_NE(report_json(r, 2).find('\n'), std::string::npos);
  const nlohmann::json j = nlohmann::json::parse(line);
  EXPECT_EQ(j.at("input"), "in/\\xFF.png");
  EXPECT_EQ(j.at("input_base64"), "aW4v/y5wbmc=");  // base64 of the bytes "in/\xff.png"
}

TEST(ImageReport, TheReverseJobsJsonHoldsEveryFieldOfItsReport) {
  ToRgbReport r;
  r.input = "in.exr", r.output = "out.png", r.output_format = "png";
  r.colorspace = "sRGB - Texture", r.kind = "reflective";
  r.width = 8, r.height = 2, r.bands = 81;
  r.first_nm = 380, r.last_nm = 780;
  r.polarised = true;
  r.mip_levels = 4;
  r.settings.colorspace = "ACEScg";  // the report's own wins
  r.settings.spectral.illuminant = "A";
  r.settings.spectral.mode = Mode::reflectance;
  r.pixels = 16, r.invalid_pixels = 1, r.half_overflow_pixels = 2, r.clipped_pixels = 3;
  r.float_overflow_pixels = 4;
  r.warnings = {"w"};
  r.seconds = 0.5;
  const nlohmann::json j = nlohmann::json::parse(report_json(r));
  EXPECT_EQ(j.at("input"), "in.exr");
  EXPECT_EQ(j.at("output"), "out.png");
  EXPECT_EQ(j.at("output_format"), "png");
  EXPECT_EQ(j.at("colorspace"), "sRGB - Texture");
  EXPECT_EQ(j.at("kind"), "reflective");
  EXPECT_EQ(j.at("width"), 8);
  EXPECT_EQ(j.at("height"), 2);
  EXPECT_EQ(j.at("bands"), 81);
  EXPECT_EQ(j.at("first_nm"), 380.0);
  EXPECT_EQ(j.at("last_nm"), 780.0);
  EXPECT_EQ(j.at("polarised"), true);
  EXPECT_EQ(j.at("input_mip_levels"), 4);
  EXPECT_EQ(j.at("illuminant"), "A");
  EXPECT_EQ(j.at("pixels"), 16);
  EXPECT_EQ(j.at("invalid_pixels"), 1);
  EXPECT_EQ(j.at("half_overflow_pixels"), 2);
  EXPECT_EQ(j.at("clipped_pixels"), 3);
  EXPECT_EQ(j.at("float_overflow_pixels"), 4);
  EXPECT_EQ(j.at("warnings"), std::vector<std::string>{"w"});
  EXPECT_EQ(j.at("seconds"), 0.5);
}

}  // namespace
}  // namespace spectralize
