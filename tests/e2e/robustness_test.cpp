// Robustness for unattended ingest, one test per class of defect, through the real binary and
// stock OIIO tools: tiled and MIP-mapped inputs, report paths, alpha, SOURCE_DATE_EPOCH,
// metadata that must describe the data, colour metadata, unusable caches, non-regular inputs,
// flags and recipes. Each test's oracle is independent: OIIO reading the files, our own
// integration of the CIE tables, or the bytes of the inputs.

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <nlohmann/json.hpp>
#include <regex>

#include "exr_support.h"

namespace fs = std::filesystem;
using e2e::max_difference;
using e2e::read_json;
using e2e::run;
using e2e::tool;
using e2e::write_image;
using Json = nlohmann::json;

namespace {

const std::string kImages = SPECTRALIZE_SOURCE_DIR "/testimages/";

struct Scratch : e2e::Scratch {
  Scratch() : e2e::Scratch("spectralize_robust") {}
};

// --- 1. Tiled and MIP-mapped inputs ---

// Truth: a tiled, a MIP-mapped and a scanline copy of one image are the same picture, so every
// command gives the same pixels from each; the report says which level was read.
TEST(Robustness, TiledAndMipMappedInputsWorkEverywhere) {
  Scratch s;
  const std::string src = kImages + "hdri_forest_256x128.exr";
  ASSERT_EQ(tool("oiiotool " + src + " --tile 64 64 -o " + (s / "tiled.exr")).exit_code, 0);
  ASSERT_EQ(tool("oiiotool " + src + " --tile 48 40 -o " + (s / "odd_tiles.exr")).exit_code, 0);
  ASSERT_EQ(tool("maketx " + src + " --format openexr -o " + (s / "mip.tx")).exit_code, 0);
  const std::string fixed = "SOURCE_DATE_EPOCH=1700000000";
  ASSERT_EQ(run(src + " -o " + (s / "ref.exr") + " -q", fixed).exit_code, 0);
  const e2e::Exr ref = e2e::read_exr(s / "ref.exr");
  for (const char* name : {"tiled.exr", "odd_tiles.exr", "mip.tx"}) {
    SCOPED_TRACE(name);
    auto r = run((s / name) + " -o " + (s / "out.exr") + " --report " + (s / "r.json"), fixed);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(max_difference(e2e::read_exr(s / "out.exr"), ref), 0.0);
    const Json rep = read_json(s / "r.json");
    EXPECT_EQ(rep["input_tiled"], true);
    EXPECT_EQ(rep["input_mip_levels"].get<int>(), std::string(name) == "mip.tx" ? 9 : 1);
    // The plugin serves the same pixels to stock oiiotool.
    std::ofstream(s / "r.spectral") << "{\"source\": \"" << name << "\"}";
    auto t = tool("oiiotool " + (s / "r.spectral") + " -o " + (s / "plugin.exr"));
    ASSERT_EQ(t.exit_code, 0) << t.out;
    EXPECT_LE(max_difference(e2e::read_exr(s / "plugin.exr"), ref), 0.0);
  }
  // --to-rgb and --plot-pixel on our own tiled output.
  ASSERT_EQ(run(src + " -o " + (s / "t16.exr") + " --tile 16 -q").exit_code, 0);
  ASSERT_EQ(run("--to-rgb " + (s / "t16.exr") + " -o " + (s / "a.exr") + " -q").exit_code, 0);
  ASSERT_EQ(run("--to-rgb " + (s / "ref.exr") + " -o " + (s / "b.exr") + " -q").exit_code, 0);
  EXPECT_EQ(max_difference(e2e::read_exr(s / "a.exr"), e2e::read_exr(s / "b.exr")), 0.0);
  auto p = run("--plot-pixel 100,50 " + (s / "t16.exr") + " -o " + (s / "p.svg"));
  EXPECT_EQ(p.exit_code, 0) << p.err;
  EXPECT_TRUE(fs::exists(s / "p.svg"));
}

// --- 2. Failed writes ---

// Truth: a write that cannot complete (file-size limit just below the file's size, /dev/full)
// exits 1 naming the file and leaves nothing at the destination, for every kind of output.
TEST(Robustness, FailedWritesAreFailuresForEveryOutput) {
  Scratch s;
  const std::string in = kImages + "hdri_sunset_256x128.exr";
  ASSERT_EQ(run(in + " -o " + (s / "full.exr") + " -q").exit_code, 0);
  const auto size = fs::file_size(s / "full.exr");
  fs::remove(s / "full.exr");
  // ulimit -f counts 1024-byte blocks: one block short of the whole file.
  const std::string limit = "ulimit -f " + std::to_string(size / 1024 - 1) + ";";
  for (const std::string& args :
       {in + " -o " + (s / "out.exr"), in + " -o " + (s / "out.exr") + " --format float",
        in + " -o " + (s / "out.exr") + " --tile 32"}) {
    auto r = run("-q " + args, limit);
    EXPECT_EQ(r.exit_code, 1) << args << ": " << r.err;
    EXPECT_NE(r.err.find("out.exr"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(s / "out.exr")) << args;
  }
  ASSERT_EQ(run(in + " -o " + (s / "spec.exr") + " -q").exit_code, 0);
  auto r = run("--to-rgb " + (s / "spec.exr") + " -o " + (s / "rgb.exr") + " -q", "ulimit -f 8;");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_FALSE(fs::exists(s / "rgb.exr"));
  r = run("--color 0.2,0.5,0.1 -o " + (s / "plot.png"), "ulimit -f 8;");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("plot.png"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(s / "plot.png"));
  // Standard output that cannot be written.
  const std::string err = s / "err.txt";
  const int status =
      std::system((std::string(SPECTRALIZE_BINARY) + " --color 1,1,1 >/dev/full 2>" + err).c_str());
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 1) << status;
  EXPECT_NE(e2e::slurp(err).find("standard output"), std::string::npos) << e2e::slurp(err);
  fs::remove(err);
  r = run("--color 1,1,1 -o /dev/full");
  EXPECT_EQ(r.exit_code, 1);
  r = run(in + " -o " + (s / "x.exr") + " -q --report /dev/full");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("/dev/full"), std::string::npos) << r.err;
  // Only the image written before the report failed... and nothing else.
  for (const auto& name : s.files()) {
    EXPECT_EQ(name.find(".tmp"), std::string::npos) << name;
  }
}

// --- 3. The report path ---

// Truth: the report never replaces an input, the output, a symlink or a device, fails before
// any work in a missing folder, and /dev/stdout, /dev/null and pipes work as streams.
TEST(Robustness, ReportPathIsCheckedBeforeAnyWork) {
  Scratch s;
  fs::copy_file(kImages + "hdri_forest_256x128.exr", s / "one.exr");
  const std::string original = e2e::slurp(s / "one.exr");
  fs::create_symlink("one.exr", s / "alias.json");
  for (const std::string& report :
       {s / "one.exr", s / "alias.json", s.dir.string() + "/./one.exr"}) {
    auto r = run((s / "one.exr") + " -o " + (s / "out.exr") + " --report " + report);
    EXPECT_EQ(r.exit_code, 1) << report << ": " << r.err;
    EXPECT_NE(r.err.find("input"), std::string::npos) << r.err;
    EXPECT_EQ(e2e::slurp(s / "one.exr"), original);
    EXPECT_FALSE(fs::exists(s / "out.exr"));
  }
  auto r = run((s / "one.exr") + " -o " + (s / "out.exr") + " --report " + (s / "out.exr"));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_FALSE(fs::exists(s / "out.exr"));
  r = run((s / "one.exr") + " -o " + (s / "out.exr") + " --report " + (s / "no/dir/r.json"));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("no/dir/r.json"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(s / "out.exr")) << "the image must not be written first";
  // Streams.
  r = run((s / "one.exr") + " -o " + (s / "a.exr") + " -q --report /dev/stdout");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(Json::parse(r.out)["pixels"], 32768);
  r = run((s / "one.exr") + " -o " + (s / "b.exr") + " -q --report /dev/null");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  ASSERT_EQ(::mkfifo((s / "fifo.json").c_str(), 0600), 0);
  const std::string cmd = "cat " + (s / "fifo.json") + " > " + (s / "fifo.out") + " & " +
                          SPECTRALIZE_BINARY + " " + (s / "one.exr") + " -o " + (s / "c.exr") +
                          " -q --report " + (s / "fifo.json") + "; wait";
  ASSERT_EQ(std::system(("sh -c '" + cmd + "'").c_str()), 0);
  EXPECT_EQ(read_json(s / "fifo.out")["pixels"], 32768);
  EXPECT_EQ(fs::status(s / "fifo.json").type(), fs::file_type::fifo);  // not replaced
  // Links not yet pointing at a file: a report linked to the output, an output linked to the
  // report; and files the run reads besides the input (its OCIO config, given or by $OCIO).
  fs::create_symlink("e.exr", s / "to_output.json");
  r = run((s / "one.exr") + " -o " + (s / "e.exr") + " -q --report " + (s / "to_output.json"));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_FALSE(fs::exists(s / "e.exr"));
  fs::create_symlink("f.json", s / "to_report.exr");
  r = run((s / "one.exr") + " -o " + (s / "to_report.exr") + " -q --report " + (s / "f.json"));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_FALSE(fs::exists(s / "f.json"));
  fs::copy_file(SPECTRALIZE_SOURCE_DIR "/ocio_configs/spectralize.ocio", s / "cfg.ocio");
  const std::string config = e2e::slurp(s / "cfg.ocio");
  fs::copy_file(s / "cfg.ocio", s / "cfg.exr");  // OCIO reads a config by any name
  for (const std::string cfg : {"cfg.ocio", "cfg.exr"}) {
    const std::string args =
        cfg == "cfg.ocio" ? " -o " + (s / "g.exr") + " --report " + (s / cfg) : " -o " + (s / cfg);
    r = run((s / "one.exr") + " -q --config " + (s / cfg) + args);
    EXPECT_EQ(r.exit_code, 1) << args << ": " << r.err;
    EXPECT_NE(r.err.find("reads"), std::string::npos) << r.err;
    EXPECT_EQ(e2e::slurp(s / cfg), config);
    EXPECT_FALSE(fs::exists(s / "g.exr"));
  }
  r = run((s / "one.exr") + " -q -o " + (s / "h.exr") + " --report " + (s / "cfg.ocio"),
          "OCIO=" + (s / "cfg.ocio"));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_EQ(e2e::slurp(s / "cfg.ocio"), config);
  // A report that cannot be written (a full device) fails the run, and the image is not left.
  for (const char* flag : {"", "--to-rgb"}) {
    const std::string in = *flag ? (s / "a.exr") : (s / "one.exr");
    r = run(std::string(flag) + " " + in + " -o " + (s / "i.exr") + " -q --report /dev/full");
    EXPECT_EQ(r.exit_code, 1) << flag << r.err;
    EXPECT_NE(r.err.find("/dev/full"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(s / "i.exr")) << flag;
  }
  // A symlink to a report is written through: the link stays a link.
  fs::create_symlink("target.json", s / "link.json");
  r = run((s / "one.exr") + " -o " + (s / "d.exr") + " -q --report " + (s / "link.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::is_symlink(s / "link.json"));
  EXPECT_EQ(read_json(s / "target.json")["pixels"], 32768);
}

// --- 5. Alpha ---

// Truth (README "Alpha"): colour is straight in PNGs; a white 8-bit pixel at alpha 64/255 is a
// reflectance of 64/255 everywhere (a white surface covering a quarter of the pixel); the
// plugin reports no alpha for sources without one; non-finite alpha is counted and clamped.
TEST(Robustness, AlphaFollowsItsStatedRules) {
  Scratch s;
  std::vector<float> px;
  for (int i = 0; i < 4; ++i) px.insert(px.end(), {1, 1, 1, 64 / 255.0f});
  write_image(s / "white.png", 2, 2, {"R", "G", "B", "A"}, OIIO::TypeUInt8, px);
  auto r = run((s / "white.png") + " -o " + (s / "w.exr") + " --format float -q");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const e2e::Exr w = e2e::read_exr(s / "w.exr");
  const int a = w.channel("A");
  ASSERT_GE(a, 0);
  for (const auto& [c, nm] : e2e::spectral_channels(w, "T.")) {
    EXPECT_NEAR(w.at(1, 1, c), 64 / 255.0, 1e-5) << nm;
  }
  EXPECT_NEAR(w.at(1, 1, a), 64 / 255.0, 1e-6);
  EXPECT_NEAR(w.at(1, 1, w.channel("R")), 64 / 255.0, 1e-4);  // previews are premultiplied too
  // A source without alpha: no alpha channel, neither in the file nor through the plugin.
  std::ofstream(s / "r.spectral") << "{\"source\": \"" << kImages << "hdri_forest_256x128.exr\"}";
  auto t = tool("iinfo -v " + (s / "r.spectral"));
  ASSERT_EQ(t.exit_code, 0) << t.out;
  EXPECT_EQ(t.out.find("alpha channel"), std::string::npos) << t.out.substr(0, 400);
  // Non-finite and out-of-range alpha in an EXR: counted, written finite within 0..1.
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = INFINITY;
  write_image(s / "bad_alpha.exr", 4, 1, {"R", "G", "B", "A"}, OIIO::TypeFloat,
              {0.5f, 0.5f, 0.5f, nan, 0.5f, 0.5f, 0.5f, inf, 0.5f, 0.5f, 0.5f, 1e30f, 0.5f, 0.5f,
               0.5f, 0.5f});
  r = run((s / "bad_alpha.exr") + " -o " + (s / "ba.exr") + " --report " + (s / "ba.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(read_json(s / "ba.json")["invalid_alpha_pixels"], 3);
  EXPECT_NE(r.err.find("alpha"), std::string::npos) << r.err;
  const e2e::Exr ba = e2e::read_exr(s / "ba.exr");
  for (float v : ba.pixels) {
    ASSERT_TRUE(std::isfinite(v));
  }
  EXPECT_EQ(ba.at(0, 0, ba.channel("A")), 0.0f);
  EXPECT_EQ(ba.at(1, 0, ba.channel("A")), 1.0f);
  EXPECT_EQ(ba.at(2, 0, ba.channel("A")), 1.0f);
}

// --- 6. SOURCE_DATE_EPOCH ---

TEST(Robustness, SourceDateEpochIsValidated) {
  Scratch s;
  const std::string in = kImages + "grey_ramp8.png";
  auto r = run(in + " -o " + (s / "a.exr"), "SOURCE_DATE_EPOCH=1700000000");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(e2e::read_exr(s / "a.exr").attributes["DateTime"], "2023:11:14 22:13:20");
  for (const char* bad : {"99999999999999999", "abc", "-5", "1e9"}) {
    r = run(in + " -o " + (s / "b.exr"), std::string("SOURCE_DATE_EPOCH=") + bad);
    EXPECT_EQ(r.exit_code, 0) << bad << ": " << r.err;
    EXPECT_NE(r.err.find("SOURCE_DATE_EPOCH"), std::string::npos) << r.err;
    EXPECT_NE(e2e::read_exr(s / "b.exr").attributes["DateTime"].substr(0, 4), "1970");
  }
}

// --- 7. Metadata that describes the data ---

TEST(Robustness, OutputTagsDescribeTheWrittenRgb) {
  Scratch s;
  // An ACEScg input tagged lin_ap1_scene: the previews are in the preview space and say so.
  write_image(s / "acescg.exr", 2, 2, {"R", "G", "B"}, OIIO::TypeFloat, {}, 0.3f,
              [](OIIO::ImageSpec& spec) { spec.attribute("colorInteropID", "lin_ap1_scene"); });
  auto r = run((s / "acescg.exr") + " -o " + (s / "o.exr") + " -q");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  e2e::Exr o = e2e::read_exr(s / "o.exr");
  EXPECT_EQ(o.attributes["colorInteropID"], "lin_rec709_scene");
  EXPECT_EQ(o.attributes["spectralize:colorspace"], "ACEScg");
  // --to-rgb into ACEScg: the AP1 primaries and ACES white, and the interop ID.
  r = run("--to-rgb " + (s / "o.exr") + " -o " + (s / "cg.exr") + " --colorspace ACEScg -q");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto in = OIIO::ImageInput::open(s / "cg.exr");
  ASSERT_TRUE(in);
  const OIIO::ParamValue* chroma =
      in->spec().find_attribute("chromaticities", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8));
  ASSERT_TRUE(chroma);
  const float* c = static_cast<const float*>(chroma->data());
  const float ap1[8] = {0.713f, 0.293f, 0.165f, 0.830f, 0.128f, 0.044f, 0.32168f, 0.33767f};
  for (int i = 0; i < 8; ++i) {
    EXPECT_NEAR(c[i], ap1[i], 1e-5) << i;
  }
  EXPECT_EQ(in->spec().get_string_attribute("colorInteropID"), "lin_ap1_scene");
  // Bispectral files are refused, not reduced to their diagonal.
  write_image(s / "bi.exr", 2, 2,
              {"T.500,000000nm", "T.500,000000nm.510,000000nm", "T.510,000000nm"}, OIIO::TypeFloat);
  r = run("--to-rgb " + (s / "bi.exr") + " -o " + (s / "x.exr"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("bispectral"), std::string::npos) << r.err;
  // Reflectances stay <= 1 bit-exactly in float output (the grey ramp's white).
  r = run(kImages + "grey_ramp8.png -o " + (s / "g.exr") + " --format float -q");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const e2e::Exr g = e2e::read_exr(s / "g.exr");
  float peak = 0;
  for (const auto& [ch, nm] : e2e::spectral_channels(g, "T."))
    for (int y = 0; y < g.height; ++y)
      for (int x = 0; x < g.width; ++x) peak = std::max(peak, g.at(x, y, ch));
  EXPECT_EQ(peak, 1.0f);
}

// An independent reading of an ICC profile: the primaries and white as the profile's chromatic
// adaptation ('chad') maps them back from its D50 colorants, the red tone curve at 0.5, and the
// description.
struct IccRead {
  bool ok = false;
  double xy[8] = {};
  double trc_half = 0;
  std::string description;
};

IccRead read_icc(const std::string& file) {
  IccRead r;
  auto in = OIIO::ImageInput::open(file);
  if (!in) return r;
  const OIIO::ParamValue* p = in->spec().find_attribute("ICCProfile");
  if (!p) return r;
  const auto* d = static_cast<const unsigned char*>(p->data());
  const std::size_t n = p->datasize();
  auto u32 = [&](std::size_t at) {
    return at + 4 <= n ? (std::uint32_t(d[at]) << 24 | std::uint32_t(d[at + 1]) << 16 |
                          std::uint32_t(d[at + 2]) << 8 | d[at + 3])
                       : 0u;
  };
  auto s15 = [&](std::size_t at) { return static_cast<std::int32_t>(u32(at)) / 65536.0; };
  auto tag = [&](const char* sig) -> std::size_t {
    for (std::uint32_t i = 0, count = u32(128); i < count; ++i)
      if (std::memcmp(d + 132 + 12 * i, sig, 4) == 0) return u32(132 + 12 * i + 4);
    return 0;
  };
  const std::size_t chad = tag("chad"), trc = tag("rTRC"), desc = tag("desc");
  if (!chad || !trc || !tag("rXYZ") || !tag("gXYZ") || !tag("bXYZ")) return r;
  double m[9];
  for (int i = 0; i < 9; ++i) m[i] = s15(chad + 8 + 4 * i);
  // The inverse of chad (D50 -> the source white) by cofactors.
  const double det = m[0] * (m[4] * m[8] - m[5] * m[7]) - m[1] * (m[3] * m[8] - m[5] * m[6]) +
                     m[2] * (m[3] * m[7] - m[4] * m[6]);
  const double inv[9] = {(m[4] * m[8] - m[5] * m[7]) / det, (m[2] * m[7] - m[1] * m[8]) / det,
                         (m[1] * m[5] - m[2] * m[4]) / det, (m[5] * m[6] - m[3] * m[8]) / det,
                         (m[0] * m[8] - m[2] * m[6]) / det, (m[2] * m[3] - m[0] * m[5]) / det,
                         (m[3] * m[7] - m[4] * m[6]) / det, (m[1] * m[6] - m[0] * m[7]) / det,
                         (m[0] * m[4] - m[1] * m[3]) / det};
  auto native_xy = [&](double X, double Y, double Z, double* out) {
    const double x = inv[0] * X + inv[1] * Y + inv[2] * Z, y = inv[3] * X + inv[4] * Y + inv[5] * Z,
                 z = inv[6] * X + inv[7] * Y + inv[8] * Z;
    out[0] = x / (x + y + z);
    out[1] = y / (x + y + z);
  };
  const char* colorants[3] = {"rXYZ", "gXYZ", "bXYZ"};
  for (int i = 0; i < 3; ++i) {
    const std::size_t at = tag(colorants[i]);
    native_xy(s15(at + 8), s15(at + 12), s15(at + 16), r.xy + 2 * i);
  }
  native_xy(0.9642, 1.0, 0.8249, r.xy + 6);  // the PCS white, D50
  if (std::memcmp(d + trc, "curv", 4) == 0 && u32(trc + 8) == 1) {
    r.trc_half = std::pow(0.5, (u32(trc + 12) >> 16) / 256.0);
  } else if (std::memcmp(d + trc, "para", 4) == 0) {
    const int type = static_cast<int>(u32(trc + 8) >> 16);
    double g[5] = {};
    for (int i = 0; i < 5; ++i) g[i] = s15(trc + 12 + 4 * i);
    if (type == 0) r.trc_half = std::pow(0.5, g[0]);
    if (type == 3) r.trc_half = 0.5 >= g[4] ? std::pow(g[1] * 0.5 + g[2], g[0]) : g[3] * 0.5;
  } else {
    return r;
  }
  if (desc && std::memcmp(d + desc, "mluc", 4) == 0) {  // UTF-16BE, the first record
    const std::size_t len = u32(desc + 20), off = u32(desc + 24);
    for (std::size_t i = 0; i + 1 < len && desc + off + i + 1 < n; i += 2)
      r.description += static_cast<char>(d[desc + off + i + 1]);
  }
  r.ok = true;
  return r;
}

// Truth (README "Honest colour tags"): every RGB file --to-rgb writes says its colour space in what
// its format holds, read back by OIIO: EXR chromaticities (also for encoded spaces) and
// colorInteropID; TIFF, PNG and JPEG an ICC profile of the space's primaries, white and curve;
// where the format cannot say it (Radiance HDR beyond linear Rec.709, a log curve in TIFF) a
// counted warning names the file and what readers will assume.
TEST(Robustness, EveryFormatSaysItsColourSpace) {
  Scratch s;
  ASSERT_EQ(run(kImages + "grey_ramp8.png -o " + (s / "g.exr") + " -q").exit_code, 0);
  const double rec709[8] = {0.64, 0.33, 0.30, 0.60, 0.15, 0.06, 0.3127, 0.3290};
  const double ap1[8] = {0.713, 0.293, 0.165, 0.830, 0.128, 0.044, 0.32168, 0.33767};
  const double adobe[8] = {0.64, 0.33, 0.21, 0.71, 0.15, 0.06, 0.3127, 0.3290};
  struct Case {
    std::string file, args;
    const double* xy;
    double trc_half;  // the curve at 0.5: sRGB's 0.21404, 2^-2.2 or 1/2
    std::string description;
  };
  const Case cases[] = {
      {"o.tif", "--format uint16", rec709, 0.214041, "sRGB - Texture (srgb_rec709_scene)"},
      {"cg.png", "--format uint16 --colorspace ACEScg", ap1, 0.5, "ACEScg (lin_ap1_scene)"},
      {"a.jpg", "--format uint8 --colorspace 'Adobe RGB (1998) - Texture'", adobe,
       std::pow(0.5, 563.0 / 256), "Adobe RGB (1998) - Texture (g22_adobergb_scene)"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.file);
    auto r = run("--to-rgb " + (s / "g.exr") + " -o " + (s / c.file) + " " + c.args + " -q");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const IccRead icc = read_icc(s / c.file);
    ASSERT_TRUE(icc.ok);
    for (int i = 0; i < 8; ++i) {
      EXPECT_NEAR(icc.xy[i], c.xy[i], 2e-4) << i;
    }
    EXPECT_NEAR(icc.trc_half, c.trc_half, 2e-4);
    EXPECT_EQ(icc.description, c.description);
  }
  // PNG also keeps the interop ID and OIIO's colour-space name.
  auto in = OIIO::ImageInput::open(s / "cg.png");
  ASSERT_TRUE(in);
  EXPECT_EQ(in->spec().get_string_attribute("colorInteropID"), "lin_ap1_scene");
  EXPECT_EQ(in->spec().get_string_attribute("oiio:ColorSpace"), "ACEScg");
  // An EXR in an encoded space: its primaries' chromaticities and its interop ID.
  ASSERT_EQ(run("--to-rgb " + (s / "g.exr") + " -o " + (s / "s.exr") +
                " --colorspace 'sRGB - Texture' -q")
                .exit_code,
            0);
  in = OIIO::ImageInput::open(s / "s.exr");
  ASSERT_TRUE(in);
  EXPECT_EQ(in->spec().get_string_attribute("colorInteropID"), "srgb_rec709_scene");
  const auto* chroma =
      in->spec().find_attribute("chromaticities", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8));
  ASSERT_TRUE(chroma);
  for (int i = 0; i < 8; ++i) {
    EXPECT_NEAR(static_cast<const float*>(chroma->data())[i], rec709[i], 1e-5) << i;
  }
  // No slot: a warning on stderr and in the report, naming the file and the assumption.
  const std::pair<std::string, std::string> unsaid[] = {
      {"cg.hdr", "--colorspace ACEScg"}, {"log.tif", "--format uint16 --colorspace ACEScct"}};
  for (const auto& [file, args] : unsaid) {
    SCOPED_TRACE(file);
    auto r = run("--to-rgb " + (s / "g.exr") + " -o " + (s / file) + " " + args + " --report " +
                 (s / "r.json"));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.err.find("WARNING: '" + (s / file) + "'"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("readers will assume"), std::string::npos) << r.err;
    const Json rep = read_json(s / "r.json");
    bool counted = false;
    for (const auto& w : rep["warnings"])
      counted = counted || w.get<std::string>().find("readers will assume") != std::string::npos;
    EXPECT_TRUE(counted) << rep.dump();
  }
  // Linear Rec.709 is what an HDR says: no warning.
  auto r = run("--to-rgb " + (s / "g.exr") + " -o " + (s / "lin.hdr"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err.find("readers will assume"), std::string::npos) << r.err;
}

// --- 8. Colour metadata ---

// A minimal ICC profile with a 'desc' tag (version 2 'desc' type), as cameras and editors embed.
std::vector<unsigned char> icc_profile(const std::string& description) {
  std::vector<unsigned char> p(128, 0);
  auto be32 = [](std::vector<unsigned char>& v, std::uint32_t x) {
    for (int i = 3; i >= 0; --i) v.push_back(static_cast<unsigned char>(x >> (8 * i)));
  };
  be32(p, 1);
  p.insert(p.end(), {'d', 'e', 's', 'c'});
  be32(p, 144);
  be32(p, static_cast<std::uint32_t>(12 + description.size() + 1));
  p.insert(p.end(), {'d', 'e', 's', 'c', 0, 0, 0, 0});
  be32(p, static_cast<std::uint32_t>(description.size() + 1));
  p.insert(p.end(), description.begin(), description.end());
  p.push_back(0);
  return p;
}

TEST(Robustness, ColourMetadataIsHonouredOrNamed) {
  Scratch s;
  const auto with_icc = [](const std::string& desc) {
    return [desc](OIIO::ImageSpec& spec) {
      const auto icc = icc_profile(desc);
      spec.attribute("ICCProfile", OIIO::TypeDesc(OIIO::TypeDesc::UINT8, icc.size()), icc.data());
    };
  };
  write_image(s / "adobe.jpg", 4, 4, {"R", "G", "B"}, OIIO::TypeUInt8, {}, 0.5f,
              with_icc("Adobe RGB (1998)"));
  auto r = run((s / "adobe.jpg") + " -o " + (s / "a.exr") + " --report " + (s / "a.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  Json rep = read_json(s / "a.json");
  EXPECT_EQ(rep["colorspace"], "Adobe RGB (1998) - Texture");
  EXPECT_NE(rep["colorspace_reason"].get<std::string>().find("ICC"), std::string::npos);
  write_image(s / "odd.jpg", 4, 4, {"R", "G", "B"}, OIIO::TypeUInt8, {}, 0.5f,
              with_icc("Wacky Printer 9000"));
  r = run((s / "odd.jpg") + " -o " + (s / "o.exr"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("Wacky Printer 9000"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("sRGB - Texture"), std::string::npos) << r.err;  // the space assumed
  // Variants of known profiles have other curves or whites: named, never taken for the standard.
  for (const char* variant : {"sRGB IEC61966-2.1 Linear", "DCI-P3"}) {
    write_image(s / "v.jpg", 4, 4, {"R", "G", "B"}, OIIO::TypeUInt8, {}, 0.5f, with_icc(variant));
    r = run((s / "v.jpg") + " -o " + (s / "v.exr") + " --report " + (s / "v.json"));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.err.find(variant), std::string::npos) << r.err;
    EXPECT_EQ(read_json(s / "v.json")["colorspace_reason"].get<std::string>().find("ICC"),
              std::string::npos)
        << variant;
  }
  // A linear-tagged PNG (gAMA 1.0): 0.5 stays 0.5 (sRGB decoding would give 0.214).
  write_image(s / "lin.png", 2, 2, {"R", "G", "B"}, OIIO::TypeUInt16, {}, 0.5f,
              [](OIIO::ImageSpec& spec) { spec.attribute("oiio:ColorSpace", "Linear"); });
  r = run((s / "lin.png") + " -o " + (s / "l.exr") + " --format float -q");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const e2e::Exr l = e2e::read_exr(s / "l.exr");
  EXPECT_NEAR(l.at(0, 0, l.channel("G")), 0.5, 1e-3);
  // Channel sets that are not colour are refused, naming the file and the channels.
  write_image(s / "rg.exr", 2, 2, {"R", "G"}, OIIO::TypeFloat);
  write_image(s / "layer.exr", 2, 2, {"diffuse.B", "diffuse.G", "diffuse.R"}, OIIO::TypeFloat);
  for (const char* name : {"rg.exr", "layer.exr"}) {
    r = run((s / name) + " -o " + (s / "x.exr"));
    EXPECT_EQ(r.exit_code, 1) << name;
    EXPECT_NE(r.err.find(name), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("not an RGB"), std::string::npos) << r.err;
  }
  r = run(kImages + "spectral_samples/colour_D65.exr -o " + (s / "x.exr"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("already a spectral image"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(s / "x.exr"));
}

// --- 11. --to-rgb on other tools' files ---

// Truth: --to-rgb never writes a NaN, Inf or silently clamped sample: non-finite samples become
// 0 and HALF overflow is clamped, both counted in a warning naming the file; channels that
// look spectral but do not parse are named; a file with no band where colour is defined
// (360-830 nm) is refused. Oracle: the written file read back with OIIO, and the messages.
TEST(Robustness, ToRgbNamesWhatItCannotWrite) {
  Scratch s;
  const std::vector<std::string> bands = {"S0.400nm", "S0.500nm", "S0.600nm", "S0.700nm"};
  std::vector<float> px(4 * 2 * bands.size(), 1.0f);
  px[0] = std::numeric_limits<float>::quiet_NaN();  // pixel 0: NaN
  px[4] = std::numeric_limits<float>::infinity();   // pixel 1: +Inf
  for (int b = 0; b < 4; ++b) px[8 + b] = 1e7f;     // pixel 2: far beyond HALF
  std::vector<std::string> names = bands;
  names.push_back("S0.5x0nm");  // spectral-looking, unparseable
  std::vector<float> with_odd;
  for (std::size_t p = 0; p < 8; ++p) {
    for (std::size_t b = 0; b < 4; ++b) with_odd.push_back(px[p * 4 + b]);
    with_odd.push_back(1.0f);
  }
  write_image(s / "odd.exr", 4, 2, names, OIIO::TypeFloat, with_odd);
  auto r = run("--to-rgb " + (s / "odd.exr") + " -o " + (s / "rgb.exr"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("2 pixels have NaN or infinite samples"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("exceed HALF's range"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("S0.5x0nm"), std::string::npos) << r.err;
  const e2e::Exr out = e2e::read_exr(s / "rgb.exr");
  for (float v : out.pixels) {
    EXPECT_TRUE(std::isfinite(v));
  }
  EXPECT_LE(out.at(2, 0, out.channel("G")), 65504.0f);
  // The NaN and Inf samples count as 0: the same pixels as a file with zeros there.
  with_odd[0] = 0.0f;
  with_odd[5] = 0.0f;
  write_image(s / "zeros.exr", 4, 2, names, OIIO::TypeFloat, with_odd);
  ASSERT_EQ(run("--to-rgb " + (s / "zeros.exr") + " -q -o " + (s / "zeros_rgb.exr")).exit_code, 0);
  const e2e::Exr ref = e2e::read_exr(s / "zeros_rgb.exr");
  for (int x : {0, 1})
    for (const char* c : {"R", "G", "B"}) {
      EXPECT_EQ(out.at(x, 0, out.channel(c)), ref.at(x, 0, ref.channel(c))) << x << c;
    }
  // No band inside 360-830 nm: refused, nothing written.
  write_image(s / "ir.exr", 2, 2, {"S0.900nm", "S0.1000nm"}, OIIO::TypeFloat);
  r = run("--to-rgb " + (s / "ir.exr") + " -o " + (s / "ir_rgb.exr"));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("360-830 nm"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(s / "ir_rgb.exr"));
}

// --- 9. Unusable caches ---

TEST(Robustness, UnusableCachesAreReportedAndRebuilt) {
  Scratch s;
  const std::string in = kImages + "hdri_forest_256x128.exr";
  const std::string cache = s / "cache";
  ASSERT_EQ(run(in + " -o " + (s / "ref.exr") + " --format float -q --cache " + cache).exit_code,
            0);
  std::string file;
  for (const auto& e : fs::directory_iterator(cache)) file = e.path().string();
  ASSERT_FALSE(file.empty());
  const e2e::Exr ref = e2e::read_exr(s / "ref.exr");
  // Poisoned: every node spectrum doubled and the checksum recomputed (FNV-1a, the documented
  // layout): valid-looking, wrong by 2x. It must be detected, and the output stay exact.
  {
    std::string b = e2e::slurp(file);
    std::size_t at = 16 + 4;
    std::uint64_t key_len, bands, entries;
    std::memcpy(&key_len, b.data() + at, 8);
    at += 8 + key_len;
    std::memcpy(&bands, b.data() + at, 8);
    std::memcpy(&entries, b.data() + at + 8, 8);
    at += 16;
    for (std::uint64_t e = 0; e < entries; ++e) {
      at += 8;
      const bool feasible = b[at++] != 0;
      for (std::uint64_t i = 0; feasible && i < bands; ++i, at += 4) {
        float v;
        std::memcpy(&v, b.data() + at, 4);
        v *= 2;
        std::memcpy(b.data() + at, &v, 4);
      }
    }
    std::uint64_t h = 1469598103934665603ull;
    for (std::size_t i = 0; i < b.size() - 8; ++i)
      h = (h ^ static_cast<unsigned char>(b[i])) * 1099511628211ull;
    std::memcpy(b.data() + b.size() - 8, &h, 8);
    std::ofstream(file, std::ios::binary) << b;
  }
  auto r = run(in + " -o " + (s / "p.exr") + " --format float --cache " + cache);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("not the spectrum of its colour"), std::string::npos) << r.err;
  EXPECT_LE(max_difference(e2e::read_exr(s / "p.exr"), ref), 1e-6);
  // A directory, a FIFO, a link to /dev/zero where the cache file should be: reported, bypassed.
  fs::remove(file);
  fs::create_directory(file);
  r = run(in + " -o " + (s / "d.exr") + " --cache " + cache);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("is a directory"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(file), std::string::npos) << r.err;
  fs::remove(file);
  ASSERT_EQ(::mkfifo(file.c_str(), 0600), 0);
  r = run("-q " + in + " -o " + (s / "f.exr") + " --cache " + cache, "timeout 20");
  EXPECT_EQ(r.exit_code, 0) << "a FIFO cache must not hang";
  fs::remove(file);
  fs::create_symlink("/dev/zero", file);
  r = run("-q " + in + " -o " + (s / "z.exr") + " --cache " + cache, "timeout 20");
  EXPECT_EQ(r.exit_code, 0);
  // --cache naming a file: run without a persistent cache, with a warning.
  std::ofstream(s / "plain") << "x";
  r = run(in + " -o " + (s / "n.exr") + " --cache " + (s / "plain"));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("without a persistent cache"), std::string::npos) << r.err;
}

// --- 10. Inputs that are not regular files, absurd sizes ---

TEST(Robustness, NonRegularInputsAndAbsurdSizesAreRefusedAtOnce) {
  Scratch s;
  ASSERT_EQ(::mkfifo((s / "in.exr").c_str(), 0600), 0);
  ASSERT_EQ(::mkfifo((s / "cfg.ocio").c_str(), 0600), 0);
  for (const std::string& args :
       {(s / "in.exr") + " -o " + (s / "o.exr"), "/dev/zero -o " + (s / "o.exr"),
        "--to-rgb " + (s / "in.exr") + " -o " + (s / "o.exr"),
        "--plot-pixel 0,0 /dev/zero -o " + (s / "o.png"),
        "--color 1,1,1 --config " + (s / "cfg.ocio"),
        kImages + "grey_ramp8.png -o " + (s / "o.exr") + " --config /dev/zero"}) {
    const auto t0 = std::chrono::steady_clock::now();
    auto r = run(args, "timeout 20");
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_TRUE(r.exit_code == 1 || r.exit_code == 2) << args << ": " << r.exit_code;
    EXPECT_NE(r.err.find("not a regular file"), std::string::npos) << args << ": " << r.err;
    EXPECT_LT(seconds, 5) << args;
  }
  // A 1-pixel-high EXR that declares 2,000,001 x 2 pixels: refused before any allocation.
  write_image(s / "wide.exr", 2, 2, {"R", "G", "B"}, OIIO::TypeFloat);
  {
    std::fstream f(s / "wide.exr", std::ios::in | std::ios::out | std::ios::binary);
    std::string b((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    const std::string key("dataWindow\0box2i\0", 17);
    const auto at = b.find(key);
    ASSERT_NE(at, std::string::npos);
    const int box[4] = {0, 0, 2000000, 1};
    f.seekp(static_cast<std::streamoff>(at + key.size() + 4));
    f.write(reinterpret_cast<const char*>(box), sizeof box);
  }
  const e2e::Measured m =
      e2e::run_measured(std::string(SPECTRALIZE_BINARY) + " " + (s / "wide.exr") + " -o " +
                        (s / "o.exr") + " 2>/dev/null");
  EXPECT_EQ(m.exit_code, 1);
#ifndef SPECTRALIZE_SANITIZED
  EXPECT_LT(m.peak_mb, 300);
#endif
  EXPECT_FALSE(fs::exists(s / "o.exr"));
}

// --- 11. Flags and recipes ---

struct BadFlag {
  const char* args;
  const char* expected;
};
class RobustnessFlags : public ::testing::TestWithParam<BadFlag> {};

TEST_P(RobustnessFlags, AreRefusedWithExitTwoNamingTheSlip) {
  auto r = run(GetParam().args);
  EXPECT_EQ(r.exit_code, 2) << GetParam().args << "\n" << r.err;
  EXPECT_NE(r.err.find(GetParam().expected), std::string::npos) << r.err;
  EXPECT_LT(r.err.size(), 2000u) << "messages do not echo huge values";
}

INSTANTIATE_TEST_SUITE_P(
    Cases, RobustnessFlags,
    ::testing::Values(
        BadFlag{"in.exr -o o.exr --threads ''", "--threads: an empty value"},
        BadFlag{"--color 1,1,1 --observer ''", "--observer: an empty value"},
        BadFlag{"--color 1,1,1 --mode ''", "--mode: an empty value"},
        BadFlag{"in.exr -o o.exr --cache ''", "--cache: an empty value"},
        BadFlag{"in.exr -o o.exr --report ''", "--report: an empty file name"},
        BadFlag{"in.exr -o ''", "-o: an empty file name"},
        BadFlag{"--color 1,1,1 --report r.json", "--report does not apply to --color"},
        BadFlag{"--color 1,1,1 --compression zip", "--compression does not apply to --color"},
        BadFlag{"--color 1,1,1 --tile 64", "--tile does not apply"},
        BadFlag{"--to-rgb x.exr -o y.exr --wavelengths 400:700:10", "--wavelengths does not apply"},
        BadFlag{"--color 1 1 1", "--color 1,1,1"},
        BadFlag{"in.exr -o o.exr --compression bogus", "--compression: 'bogus'"},
        BadFlag{"--color 1,1,1 --colorspace "
                "ZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZ"
                "ZZZZZ"
                "ZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZ"
                "ZZZZZ",
                "bytes)"}));

TEST(Robustness, DoubleDashAndLongNamesWork) {
  Scratch s;
  fs::copy_file(kImages + "grey_ramp8.png", s / "-dash.png");
  auto r = run("-q -o " + (s / "a.exr") + " -- -dash.png", "cd " + s.dir.string() + " &&");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(s / "a.exr"));
  // An output name of 255 bytes (NAME_MAX): the temporary name fits too.
  const std::string name = std::string(251, 'n') + ".exr";
  r = run(kImages + "grey_ramp8.png -q -o " + (s / name));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(s / name));
  // --help gives the real default of --filter.
  r = run("--help");
  EXPECT_EQ(r.exit_code, 0);
  const std::regex filter(R"(--filter K[^\[]*\[auto\])");
  EXPECT_TRUE(std::regex_search(r.out, filter)) << r.out.substr(0, 3000);
}

// Recipes and the CLI share one schema: the same values are accepted and refused.
TEST(Robustness, RecipesRefuseWhatTheCliRefuses) {
  Scratch s;
  fs::copy_file(kImages + "grey_ramp8.png", s / "grey.png");
  for (const char* recipe :
       {R"({"source": "grey.png", "compression": "bogus"})", R"({"source": "grey.png", "tile": 7})",
        R"({"source": "grey.png", "threads": ""})", R"({"source": "grey.png", "report": "x"})"}) {
    std::ofstream(s / "r.spectral") << recipe;
    auto t = tool("oiiotool " + (s / "r.spectral") + " -o " + (s / "o.exr"));
    EXPECT_NE(t.exit_code, 0) << recipe;
    EXPECT_NE(t.out.find("r.spectral"), std::string::npos) << t.out;
  }
  // Recipes over 64 KB are refused (README), with a short message.
  std::ofstream(s / "big.spectral")
      << "{\"source\": \"grey.png\", \"x\": \"" << std::string(70000, 'y') << "\"}";
  auto t = tool("oiiotool " + (s / "big.spectral") + " -o " + (s / "o.exr"));
  EXPECT_NE(t.exit_code, 0);
  EXPECT_LT(t.out.size(), 2000u);
}

}  // namespace
