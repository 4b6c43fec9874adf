// Hardening: bad pixels, bad headers, failing writes, extreme sizes, determinism and shared
// caches, each through the real binary.

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>

#include "exr_support.h"

namespace fs = std::filesystem;
using e2e::run;
using e2e::write_exr;
using Json = nlohmann::json;

namespace {

const std::string kImages = SPECTRALIZE_SOURCE_DIR "/testimages/";

struct Scratch : e2e::Scratch {
  Scratch() : e2e::Scratch("spectralize_hard") {}
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

// NaN, +Inf, -Inf, negative and HALF-overflowing pixels: the job completes, the output is
// finite, the counts are right, warnings are printed.
TEST(Hardening, BadPixelsAreCountedAndWrittenFinite) {
  Scratch s;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  write_exr(s / "bad.exr", 4, 2,
            {nan,  0.5f, 0.5f, inf,  0.5f, 0.5f, -inf, 0.5f, 0.5f, -0.2f, -0.3f, -0.1f,  // row 0
             1e6f, 1e6f, 1e6f, 0.2f, 0.3f, 0.4f, 0,    0,    0,    1,     1,     1});    // row 1
  auto r = run((s / "bad.exr") + " -o " + (s / "out.exr") + " --report " + (s / "r.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("3 pixels are NaN or infinite"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("--format float"), std::string::npos) << r.err;  // HALF overflow warning
  std::ifstream f(s / "r.json");
  Json rep = Json::parse(f);
  EXPECT_EQ(rep["invalid_pixels"], 3);
  EXPECT_EQ(rep["out_of_gamut"]["negative_luminance"], 1);
  EXPECT_EQ(rep["black_pixels"], 1);
  EXPECT_EQ(rep["half_overflow_pixels"], 1);
  e2e::Exr e = e2e::read_exr(s / "out.exr");
  for (float v : e.pixels) {
    ASSERT_TRUE(std::isfinite(v));
  }
}

TEST(Hardening, AbsurdAndEmptyHeadersFailFast) {
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

// A 65,536-pixel-wide strip streams a row at a time: bounded memory.
TEST(Hardening, VeryWideStripRunsInBoundedMemory) {
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

// Writes that fail: past a file-size limit (part-way), and into a place that cannot be written.
TEST(Hardening, FailingWritesLeaveNothingBehind) {
  Scratch s;
  fs::copy_file(kImages + "hdri_sunset_256x128.exr", s / "in.exr");
  auto r = run("-q " + (s / "in.exr") + " -o " + (s / "out.exr"), "ulimit -f 2000;");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("out.exr"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("write failed"), std::string::npos) << r.err;
  EXPECT_EQ(s.files(), std::vector<std::string>{"in.exr"});  // no partial or temporary file
  r = run((s / "in.exr") + " -o /proc/self/out.exr");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("/proc/self/out.exr"), std::string::npos) << r.err;
  EXPECT_EQ(fs::file_size(s / "in.exr"), fs::file_size(kImages + "hdri_sunset_256x128.exr"));
}

// With the date fixed, the same input gives byte-identical files for any thread count.
TEST(Hardening, OutputIsByteIdenticalAcrossRunsAndThreads) {
  Scratch s;
  const std::string in = kImages + "hdri_forest_256x128.exr";
  const std::string env = "SOURCE_DATE_EPOCH=1700000000";
  ASSERT_EQ(run(in + " -o " + (s / "a.exr") + " --threads 1", env).exit_code, 0);
  ASSERT_EQ(run(in + " -o " + (s / "b.exr") + " --threads 2", env).exit_code, 0);
  ASSERT_EQ(run(in + " -o " + (s / "c.exr") + " --threads 2", env).exit_code, 0);
  const std::string a = e2e::slurp(s / "a.exr");
  EXPECT_FALSE(a.empty());
  EXPECT_EQ(a, e2e::slurp(s / "b.exr"));
  EXPECT_EQ(a, e2e::slurp(s / "c.exr"));
}

// Two processes filling one --cache folder at once both succeed and leave a valid cache.
TEST(Hardening, TwoProcessesShareOneCache) {
  Scratch s;
  const std::string bin = SPECTRALIZE_BINARY;
  const std::string cache = s / "cache";
  const std::string cmd = bin + " " + kImages + "hdri_forest_256x128.exr -o " + (s / "a.exr") +
                          " -q --cache " + cache + " & " + bin + " " + kImages +
                          "hdri_sunset_256x128.exr -o " + (s / "b.exr") + " -q --cache " + cache +
                          " & wait";
  ASSERT_EQ(std::system(("sh -c '" + cmd + "'").c_str()), 0);
  EXPECT_TRUE(fs::exists(s / "a.exr"));
  EXPECT_TRUE(fs::exists(s / "b.exr"));
  auto r = run(kImages + "hdri_forest_256x128.exr -o " + (s / "c.exr") + " -v --cache " + cache);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err.find("rebuilt"), std::string::npos) << r.err;  // intact, whoever wrote last
  EXPECT_NE(r.err.find("loaded"), std::string::npos) << r.err;
  std::size_t tmp_files = 0;
  for (const auto& e : fs::directory_iterator(cache))
    tmp_files += e.path().filename().string().find(".tmp") != std::string::npos;
  EXPECT_EQ(tmp_files, 0u);
}

}  // namespace
