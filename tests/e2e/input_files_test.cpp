// Input files through the real binary and stock OIIO tools (the guide's "Files and guarantees"
// (docs/guide/files.md), Inputs): tiled, MIP-mapped and 65,536-pixel-wide inputs are read like any
// other, every command giving the same pixels, in bounded memory; absurd, empty and oversized
// headers and inputs that are not regular files are refused at once with a non-zero exit, naming
// the file, nothing written. The oracles are OIIO reading the files, the exit status and message,
// wall time and peak memory.

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "exr_support.h"

namespace fs = std::filesystem;
using e2e::max_difference;
using e2e::read_json;
using e2e::run;
using e2e::tool;
using e2e::write_exr;
using e2e::write_image;
using Json = nlohmann::json;

namespace {

const std::string kImages = SPECTRALIZE_SOURCE_DIR "/testimages/";

struct Scratch : e2e::Scratch {
  Scratch() : e2e::Scratch("spectralize_inputs") {}
};

// Rewrites the dataWindow of an EXR header (box2i: xmin, ymin, xmax, ymax).
void patch_data_window(const std::string& path, int xmax, int ymax) {
  std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  const std::string key("dataWindow\0box2i\0", 17);
  const auto at = bytes.find(key);
  ASSERT_NE(at, std::string::npos);
  const int box[4] = {0, 0, xmax, ymax};
  f.seekp(static_cast<std::streamoff>(at + key.size() + 4));
  f.write(reinterpret_cast<const char*>(box), sizeof box);
}

// Truth: a tiled, a MIP-mapped and a scanline copy of one image are the same picture, so every
// command gives the same pixels from each; the report says which level was read.
TEST(InputFiles, TiledAndMipMappedInputsWorkEverywhere) {
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

// A 65,536-pixel-wide strip streams a row at a time: bounded memory.
TEST(InputFiles, VeryWideStripRunsInBoundedMemory) {
  Scratch s;
  std::vector<float> rgb(65536 * 3);
  for (std::size_t i = 0; i < 65536; ++i) {
    rgb[i * 3] = 0.1f + 0.8f * i / 65536.0f;
    rgb[i * 3 + 1] = 0.5f;
    rgb[i * 3 + 2] = 0.9f - 0.8f * i / 65536.0f;
  }
  write_exr(s / "wide.exr", 65536, 1, rgb);
  const std::string cmd =
      std::string(SPECTRALIZE_BINARY) + " " + (s / "wide.exr") + " -o " + (s / "out.exr") + " -q";
  const e2e::Measured m = e2e::run_measured(cmd);
  EXPECT_EQ(m.exit_code, 0);
#ifndef SPECTRALIZE_SANITIZED
  EXPECT_LE(m.peak_mb, 500.0);
#endif
  int width = 0;
  EXPECT_EQ(e2e::exr_format(s / "out.exr", &width), "half");
  EXPECT_EQ(width, 65536);
}

TEST(BadInputFiles, AbsurdAndEmptyHeadersFailFast) {
  Scratch s;
  write_exr(s / "one.exr", 1, 1, {0.2f, 0.3f, 0.4f});
  fs::copy_file(s / "one.exr", s / "huge.exr");
  fs::copy_file(s / "one.exr", s / "big.exr");
  fs::copy_file(s / "one.exr", s / "empty.exr");
  patch_data_window(s / "huge.exr", 2000000000, 2000000000);
  patch_data_window(s / "big.exr", 99999, 99999);  // 10^10 pixels claimed, none stored
  patch_data_window(s / "empty.exr", -1, -1);      // 0 x 0
  // A 1x1 image is fine.
  auto r = run((s / "one.exr") + " -o " + (s / "one_out.exr"));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  for (const char* name : {"huge.exr", "big.exr", "empty.exr"}) {
    auto start = std::chrono::steady_clock::now();
    r = run((s / name) + " -o " + (s / "out.exr"));
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_EQ(r.exit_code, 1) << name << ": " << r.err;
    EXPECT_NE(r.err.find(name), std::string::npos) << r.err;
    EXPECT_LT(seconds, 10.0) << name;  // refused at open, not after allocating the claim
    EXPECT_FALSE(fs::exists(s / "out.exr"));
  }
}

TEST(BadInputFiles, NonRegularInputsAndAbsurdSizesAreRefusedAtOnce) {
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

}  // namespace
