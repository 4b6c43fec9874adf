// The node cache's file (pipeline/table_cache.h): a round trip, and the refusal of files that
// are not what they claim. The file name's hash is FNV-1a of the key, as documented.

#include "pipeline/table_cache.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "core/tables/spectral_table.h"
#include "file_test_support.h"

namespace fs = std::filesystem;

namespace spectralize {
namespace {

TEST(TableCache, RoundTripAndRefusals) {
  const test::TempDir t("cache");
  const fs::path& dir = t.dir;
  SpectralizerSettings ss;
  const Spectralizer sp(ss);
  SpectralTable made(sp);
  const Xyz c{0.3, 0.35, 0.4};
  std::vector<float> out(sp.settings().grid.size());
  PixelResult res;
  made.spectra(&c, 1, out.data(), &res);
  const std::string key = "test key";
  const std::string file = table_cache_file(dir.string(), key);
  // Stable name: the published FNV-1a 64 of the key (docs/DESIGN.md §14), whatever the standard
  // library; f5f3c17326def1e6 is that hash of "test key" (basis 0xcbf29ce484222325, prime
  // 0x100000001b3).
  EXPECT_EQ(fs::path(file).filename(), "spectralize-table-f5f3c17326def1e6.bin");
  EXPECT_EQ(save_table_cache(made, file, key), "");
  SpectralTable loaded(sp);
  EXPECT_EQ(load_table_cache(loaded, file, key), "");
  EXPECT_EQ(loaded.stats().nodes_loaded, 4u);
  SpectralTable other(sp);
  EXPECT_NE(load_table_cache(other, file, "another key").find("other settings"), std::string::npos);
  // Truncated by one byte: the checksum catches it.
  fs::resize_file(file, fs::file_size(file) - 1);
  EXPECT_NE(load_table_cache(other, file, key), "");
  // A directory or a FIFO where the file should be: refused without blocking.
  fs::remove(file);
  fs::create_directory(file);
  EXPECT_EQ(load_table_cache(other, file, key), "is a directory");
  EXPECT_NE(save_table_cache(made, file, key), "");
  fs::remove(file);
  EXPECT_EQ(load_table_cache(other, file, key), "");  // absent: nothing to load, no complaint
}

}  // namespace
}  // namespace spectralize
