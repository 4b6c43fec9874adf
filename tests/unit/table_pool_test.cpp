// The pool of spectralizers and node tables a batch shares (pipeline/table_pool.h,
// docs/DESIGN.md §4): settings the spectra do not depend on share one entry, settings they do
// depend on (mode, wavelengths, illuminant, method, a reflectance's frame) get their own, and an
// emission table, whose cells are CIE xy, is one for every frame; with a cache folder an entry
// loads its file once, saves only what grew, merges what other processes saved meanwhile, and
// reports an unusable folder or file instead of failing; a table first made without a folder
// does not stand in for settings that ask for one later. Oracles: the nodes each case computes,
// counted by a table of its own, and the files in the folder.

#include "pipeline/table_pool.h"

#include <gtest/gtest.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "core/work_counts.h"
#include "file_test_support.h"
#include "pipeline/table_cache.h"
#include "test_support.h"

namespace fs = std::filesystem;

namespace spectralize {
namespace {

const LogFn kQuiet = [](int, const std::string&) {};

// The messages said at level 0.
struct Warnings {
  std::vector<std::string> said;
  LogFn log() {
    return [this](int level, const std::string& m) {
      if (level == 0) said.push_back(m);
    };
  }
};

// Emission settings on a coarse grid (cheap node solves), mode resolved.
Settings settings_of(Mode mode = Mode::emission) {
  Settings s;
  s.mode = mode == Mode::emission ? ModeChoice::emission : ModeChoice::reflectance;
  s.spectral.mode = mode;
  s.spectral.grid = WavelengthGrid(400, 700, 20);
  return s;
}

Mat3 frame_of(const test::Mat3& m) {
  Mat3 f;
  for (int i = 0; i < 9; ++i) f[i] = m[i / 3][i % 3];
  return f;
}

// Spectra of `colours` through an entry's table: computes the nodes they need.
void use(TablePool::Entry& e, const std::vector<Xyz>& colours) {
  std::vector<float> out(colours.size() * e.table->bands());
  std::vector<PixelResult> results(colours.size());
  e.table->spectra(colours.data(), colours.size(), out.data(), results.data());
}

// The nodes `colours` need, counted on a table of their own.
std::uint64_t nodes_needed(const Settings& s, const std::vector<Xyz>& colours) {
  const Spectralizer sp(s.spectral);
  SpectralTable t(sp);
  std::vector<float> out(colours.size() * t.bands());
  std::vector<PixelResult> results(colours.size());
  t.spectra(colours.data(), colours.size(), out.data(), results.data());
  return t.stats().nodes_computed;
}

const std::vector<Xyz> kReds = {{0.4, 0.25, 0.05}, {0.5, 0.3, 0.08}};
const std::vector<Xyz> kBlues = {{0.2, 0.15, 0.6}, {0.18, 0.1, 0.7}};

TEST(TablePool, SettingsTheSpectraDoNotDependOnShareOneEntry) {
  TablePool pool;
  Settings s = settings_of();
  TablePool::Entry& a = pool.get(s, kRec709Frame, kQuiet);
  s.threads = 3;
  s.half = false;
  s.compression = "piz";
  s.preview_colorspace = "ACEScg";
  s.colorspace = "ACEScg";
  TablePool::Entry& b = pool.get(s, kRec709Frame, kQuiet);
  EXPECT_EQ(&a, &b);
  // Nodes computed through one are there for the other.
  use(a, kReds);
  const std::uint64_t computed = a.table->stats().nodes_computed;
  EXPECT_GT(computed, 0u);
  use(b, kReds);
  EXPECT_EQ(b.table->stats().nodes_computed, computed);
}

TEST(TablePool, SettingsTheSpectraDependOnGetTheirOwnEntry) {
  TablePool pool;
  const Settings base = settings_of(Mode::reflectance);
  TablePool::Entry* first = &pool.get(base, kRec709Frame, kQuiet);
  std::vector<TablePool::Entry*> entries = {first};
  Settings emission = settings_of(Mode::emission);
  Settings grid = base;
  grid.spectral.grid = WavelengthGrid(400, 700, 10);
  Settings illuminant = base;
  illuminant.spectral.illuminant = "A";
  Settings exact = base;
  exact.method = SpectralTable::Method::exact;
  for (const Settings& s : {emission, grid, illuminant, exact})
    entries.push_back(&pool.get(s, kRec709Frame, kQuiet));
  // A reflectance's cells are in the RGB of its frame.
  entries.push_back(&pool.get(base, frame_of(test::kRec2020ToXyz), kQuiet));
  for (std::size_t i = 0; i < entries.size(); ++i)
    for (std::size_t j = i + 1; j < entries.size(); ++j) {
      EXPECT_NE(entries[i], entries[j]) << i << " and " << j;
      EXPECT_NE(entries[i]->key, entries[j]->key) << i << " and " << j;
    }
  EXPECT_EQ(entries[2]->table->bands(), 31u);
  // And each is found again.
  EXPECT_EQ(&pool.get(illuminant, kRec709Frame, kQuiet), entries[3]);
  EXPECT_EQ(&pool.get(base, kRec709Frame, kQuiet), first);
}

TEST(TablePool, AnEmissionTableIsOneForEveryFrame) {
  // Emission cells lie on CIE xy (docs/DESIGN.md §14): the space's frame does not shape them.
  TablePool pool;
  const Settings s = settings_of(Mode::emission);
  TablePool::Entry& a = pool.get(s, kRec709Frame, kQuiet);
  EXPECT_EQ(&pool.get(s, frame_of(test::kRec2020ToXyz), kQuiet), &a);
}

TEST(TablePool, ConcurrentGetsOfOneSettingGetOneEntry) {
  TablePool pool;
  const Settings s = settings_of();
  std::vector<TablePool::Entry*> got(4, nullptr);
  std::vector<std::thread> threads;
  for (std::size_t i = 0; i < got.size(); ++i)
    threads.emplace_back([&, i] { got[i] = &pool.get(s, kRec709Frame, kQuiet); });
  for (auto& t : threads) t.join();
  for (TablePool::Entry* e : got) EXPECT_EQ(e, got[0]);
}

// Files of one kind that start together (a batch's jobs) build one spectralizer: those arriving
// while it is built wait for it (counted by core/work_counts.h, eight rounds of four threads).
TEST(TablePool, ConcurrentFirstGetsBuildOneSpectralizer) {
  for (int round = 0; round < 8; ++round) {
    TablePool pool;
    const Settings s = settings_of(Mode::reflectance);
    const WorkCounts before = work_counts();
    std::vector<TablePool::Entry*> got(4, nullptr);
    std::vector<std::thread> threads;
    for (std::size_t i = 0; i < got.size(); ++i)
      threads.emplace_back([&, i] { got[i] = &pool.get(s, kRec709Frame, kQuiet); });
    for (auto& t : threads) t.join();
    EXPECT_EQ(work_counts().since(before).spectralizers_built, 1u) << "round " << round;
    for (TablePool::Entry* e : got) EXPECT_EQ(e, got[0]);
  }
}

// A failure to build is every waiting caller's, and a later call tries again.
TEST(TablePool, AFailedBuildIsThrownToEveryCallerAndTriedAgainLater) {
  TablePool pool;
  Settings s = settings_of();
  // An illuminant no table knows: the spectralizer's construction throws.
  s.spectral.mode = Mode::reflectance;
  s.spectral.illuminant = "no such illuminant";
  std::vector<std::thread> threads;
  std::atomic<int> failed{0};
  for (int i = 0; i < 3; ++i)
    threads.emplace_back([&] {
      try {
        (void)pool.get(s, kRec709Frame, kQuiet);
      } catch (const Error&) {
        ++failed;
      }
    });
  for (auto& t : threads) t.join();
  EXPECT_EQ(failed, 3);
  EXPECT_THROW((void)pool.get(s, kRec709Frame, kQuiet), Error);
}

TEST(TablePool, ACacheFolderIsLoadedOnceAndSavedWhenTheTableGrew) {
  test::TempDir t("table_pool");
  Settings s = settings_of();
  s.cache_dir = t / "cache";  // made when missing
  std::uint64_t computed = 0;
  {
    TablePool pool;
    TablePool::Entry& e = pool.get(s, kRec709Frame, kQuiet);
    ASSERT_FALSE(e.cache_file.empty());
    EXPECT_EQ(fs::path(e.cache_file).parent_path(), fs::path(s.cache_dir));
    EXPECT_EQ(e.cache_file, table_cache_file(s.cache_dir, e.file_key));
    EXPECT_EQ(e.cache_status, "new");
    EXPECT_TRUE(pool.save().empty());
    EXPECT_FALSE(fs::exists(e.cache_file));  // nothing computed: nothing saved
    use(e, kReds);
    computed = e.table->stats().nodes_computed;
    EXPECT_TRUE(pool.save().empty());
    ASSERT_TRUE(fs::exists(e.cache_file));
    // Saved once: without growth it is not written again.
    fs::remove(e.cache_file);
    EXPECT_TRUE(pool.save().empty());
    EXPECT_FALSE(fs::exists(e.cache_file));
    use(e, kBlues);  // grew again: saved again
    EXPECT_TRUE(pool.save().empty());
    EXPECT_TRUE(fs::exists(e.cache_file));
    computed = e.table->stats().nodes_computed;
  }
  TablePool pool;
  TablePool::Entry& e = pool.get(s, kRec709Frame, kQuiet);
  EXPECT_EQ(e.cache_status, "loaded");
  EXPECT_EQ(e.table->stats().nodes_loaded, computed);
  use(e, kReds);
  use(e, kBlues);
  EXPECT_EQ(e.table->stats().nodes_computed, 0u);  // every node came from the file
}

TEST(TablePool, TwoPoolsSavingToOneFolderAddUp) {
  test::TempDir t("table_pool");
  Settings s = settings_of();
  s.cache_dir = t.dir.string();
  TablePool one, two;
  TablePool::Entry& a = one.get(s, kRec709Frame, kQuiet);
  TablePool::Entry& b = two.get(s, kRec709Frame, kQuiet);  // both loaded an empty folder
  use(a, kReds);
  use(b, kBlues);
  EXPECT_TRUE(one.save().empty());
  EXPECT_TRUE(two.save().empty());  // adopts what `one` saved, then writes both
  std::vector<Xyz> both = kReds;
  both.insert(both.end(), kBlues.begin(), kBlues.end());
  TablePool three;
  EXPECT_EQ(three.get(s, kRec709Frame, kQuiet).table->stats().nodes_loaded, nodes_needed(s, both));
}

TEST(TablePool, TheExactMethodHasNoCacheFile) {
  test::TempDir t("table_pool");
  Settings s = settings_of();
  s.cache_dir = t.dir.string();
  s.method = SpectralTable::Method::exact;
  TablePool pool;
  TablePool::Entry& e = pool.get(s, kRec709Frame, kQuiet);
  EXPECT_TRUE(e.cache_file.empty());
  use(e, kReds);
  EXPECT_TRUE(pool.save().empty());
  EXPECT_TRUE(fs::is_empty(t.dir));
}

TEST(TablePool, AFolderThatCannotBeMadeIsSaidAndTheWorkGoesOn) {
  test::TempDir t("table_pool");
  std::ofstream(t / "file") << "not a folder";
  Settings s = settings_of();
  s.cache_dir = t / "file";
  Warnings w;
  TablePool pool;
  TablePool::Entry& e = pool.get(s, kRec709Frame, w.log());
  EXPECT_TRUE(e.cache_file.empty());
  ASSERT_EQ(w.said.size(), 1u);
  EXPECT_EQ(w.said[0].rfind("--cache '" + s.cache_dir + "'", 0), 0u) << w.said[0];
  EXPECT_NE(w.said[0].find("without a persistent cache"), std::string::npos) << w.said[0];
  use(e, kReds);
  EXPECT_TRUE(pool.save().empty());
  // The option as the caller spells it (Python: a keyword).
  Warnings python;
  TablePool other;
  other.get(s, kRec709Frame, python.log(), "cache");
  ASSERT_EQ(python.said.size(), 1u);
  EXPECT_EQ(python.said[0].rfind("cache '" + s.cache_dir + "'", 0), 0u) << python.said[0];
}

TEST(TablePool, ADamagedCacheFileIsSaidAndRebuilt) {
  test::TempDir t("table_pool");
  Settings s = settings_of();
  s.cache_dir = t.dir.string();
  std::string file;
  {
    TablePool pool;
    TablePool::Entry& e = pool.get(s, kRec709Frame, kQuiet);
    use(e, kReds);
    ASSERT_TRUE(pool.save().empty());
    file = e.cache_file;
  }
  fs::resize_file(file, fs::file_size(file) - 1);
  Warnings w;
  TablePool pool;
  TablePool::Entry& e = pool.get(s, kRec709Frame, w.log());
  EXPECT_EQ(e.cache_status.rfind("rebuilt: ", 0), 0u) << e.cache_status;
  EXPECT_EQ(e.table->stats().nodes_loaded, 0u);  // nothing of it trusted
  ASSERT_EQ(w.said.size(), 1u);
  EXPECT_NE(w.said[0].find("'" + file + "'"), std::string::npos) << w.said[0];
  use(e, kReds);
  EXPECT_TRUE(pool.save().empty());  // and written anew
  TablePool again;
  EXPECT_EQ(again.get(s, kRec709Frame, kQuiet).cache_status, "loaded");
}

TEST(TablePool, ATableFirstMadeWithoutACacheFolderStillUsesOneAskedLater) {
  // One process, two calls: without cache, then with it (the Python module's pool lives as long
  // as the process). The second call's folder must be the one loaded and saved.
  test::TempDir t("table_pool");
  TablePool pool;
  const Settings plain = settings_of();
  Settings cached = plain;
  cached.cache_dir = t.dir.string();
  use(pool.get(plain, kRec709Frame, kQuiet), kReds);
  TablePool::Entry& e = pool.get(cached, kRec709Frame, kQuiet);
  EXPECT_EQ(fs::path(e.cache_file).parent_path(), t.dir);
  use(e, kBlues);
  EXPECT_TRUE(pool.save().empty());
  EXPECT_FALSE(fs::is_empty(t.dir));
}

}  // namespace
}  // namespace spectralize
