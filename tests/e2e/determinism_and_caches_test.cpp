// Runs that repeat or share, through the real binary (the guide's "Files and guarantees"
// (docs/guide/files.md), Determinism, Caches): with SOURCE_DATE_EPOCH set the file is
// byte-identical whatever
// --threads, and a value it cannot hold is warned about and ignored; two processes sharing one
// --cache both succeed and leave an intact file; a cache file that is poisoned, a directory, a
// FIFO or a link to a device, and a --cache that is not a folder, are reported and bypassed, the
// output exact. The oracles are the outputs' bytes, OIIO reading them, and the messages.

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "exr_support.h"

namespace fs = std::filesystem;
using e2e::max_difference;
using e2e::run;

namespace {

const std::string kImages = SPECTRALIZE_SOURCE_DIR "/testimages/";

struct Scratch : e2e::Scratch {
  Scratch() : e2e::Scratch("spectralize_determinism") {}
};

// With the date fixed, the same input gives byte-identical files for any thread count.
TEST(Determinism, OutputIsByteIdenticalAcrossRunsAndThreads) {
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

TEST(Determinism, SourceDateEpochIsValidated) {
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

// Two processes filling one --cache folder at once both succeed and leave a valid cache.
TEST(Caches, TwoProcessesShareOneCache) {
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

TEST(Caches, UnusableCachesAreReportedAndRebuilt) {
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
    std::uint64_t h = 0xcbf29ce484222325ull;  // FNV-1a 64's published offset basis
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

}  // namespace
