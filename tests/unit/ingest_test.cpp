// Batch ingest runs (ingest/ingest.h) through its public functions on small libraries written
// here (the plan itself: ingest_plan_test.cpp): a run counts every file by status, a rerun
// converts only what changed (how a batch runs never makes its outputs stale), a stop before
// the start converts nothing and says so; shard manifests merge into the batch's and a part of
// another batch is refused. Oracles: the files each case writes, the documented name pattern
// ("{dir}/{stem}.exr") and manifest names, and the file system.

#include "ingest/ingest.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "file_test_support.h"
#include "ingest_test_support.h"
#include "spectralize/core/error.h"
#include "test_support.h"

namespace fs = std::filesystem;
using Json = nlohmann::json;

namespace spectralize {
namespace {

struct TempDir : test::TempDir {
  TempDir() : test::TempDir("ingest") {}
};

const LogFn kQuiet = [](int, const std::string&) {};

using test::request_for;
using test::write_png;

std::vector<Json> manifest_lines(const std::string& path) {
  std::vector<Json> out;
  std::ifstream f(path);
  for (std::string line; std::getline(f, line);) out.push_back(Json::parse(line));
  return out;
}

// --- Runs ---

TEST(IngestRun, ARunCountsEveryFileAndARerunConvertsOnlyWhatChanged) {
  TempDir t;
  const fs::path lib = t.dir / "lib", out = t.dir / "out";
  write_png(lib / "a_basecolor.png");
  write_png(lib / "b_normal.png");                        // data by its name: never converted
  std::ofstream(lib / "c_basecolor.png") << "not a png";  // fails alone
  IngestRequest r = request_for({lib.string()}, out.string());
  r.settings.ingest.jobs = 2;
  std::vector<std::pair<std::uint64_t, std::uint64_t>> told;
  const IngestProgressFn progress = [&](std::uint64_t done, std::uint64_t total,
                                        const std::string&) { told.emplace_back(done, total); };
  const IngestSummary first = run_ingest(plan_ingest(r), progress, kQuiet);
  EXPECT_EQ(first.converted, 1u);
  EXPECT_EQ(first.skipped_data, 1u);
  EXPECT_EQ(first.failed, 1u);
  EXPECT_EQ(first.files(), 3u);
  EXPECT_EQ(first.pixels, 16u);  // the one 4 x 4 image converted
  EXPECT_FALSE(first.ok());
  ASSERT_EQ(first.failures.size(), 1u);
  EXPECT_NE(first.failures[0].find("c_basecolor.png"), std::string::npos) << first.failures[0];
  ASSERT_EQ(told.size(), 3u);
  EXPECT_EQ(told.back(), (std::pair<std::uint64_t, std::uint64_t>{3, 3}));
  const fs::path made = out / "a_basecolor.exr";
  ASSERT_TRUE(fs::exists(made));
  EXPECT_FALSE(fs::exists(out / "b_normal.exr"));
  EXPECT_FALSE(fs::exists(out / "c_basecolor.exr"));
  // The manifest: a record per file, then the summary, which says the same.
  const std::vector<Json> m = manifest_lines(first.manifest);
  ASSERT_EQ(m.size(), 4u);
  EXPECT_EQ(m.back()["summary"]["converted"], 1);
  EXPECT_EQ(m.back()["summary"]["failed"], 1);
  // Run otherwise (threads, jobs): nothing is stale, nothing rewritten.
  const auto when = fs::last_write_time(made);
  r.settings.threads = 1;
  r.settings.ingest.jobs = 1;
  const IngestSummary again = run_ingest(plan_ingest(r), {}, kQuiet);
  EXPECT_EQ(again.up_to_date, 1u);
  EXPECT_EQ(again.converted, 0u);
  EXPECT_EQ(fs::last_write_time(made), when);
  // A setting that shapes the file: converted again; and --force.
  r.settings.spectral.grid = WavelengthGrid(400, 700, 10);
  EXPECT_EQ(run_ingest(plan_ingest(r), {}, kQuiet).converted, 1u);
  r.force = true;
  EXPECT_EQ(run_ingest(plan_ingest(r), {}, kQuiet).converted, 1u);
}

TEST(IngestRun, AStopBeforeTheStartConvertsNothingAndTheManifestSaysSo) {
  TempDir t;
  const fs::path lib = t.dir / "lib", out = t.dir / "out";
  write_png(lib / "a_basecolor.png");
  write_png(lib / "b_basecolor.png");
  const std::atomic<bool> stop{true};
  const IngestSummary sum =
      run_ingest(plan_ingest(request_for({lib.string()}, out.string())), {}, kQuiet, &stop);
  EXPECT_TRUE(sum.interrupted);
  EXPECT_EQ(sum.not_done, 2u);
  EXPECT_EQ(sum.files(), 0u);
  EXPECT_FALSE(fs::exists(out / "a_basecolor.exr"));
  EXPECT_FALSE(fs::exists(out / "b_basecolor.exr"));
  const std::vector<Json> m = manifest_lines(sum.manifest);
  ASSERT_EQ(m.size(), 1u);  // no file's record: a rerun does them all
  EXPECT_EQ(m[0]["summary"]["interrupted"], true);
  EXPECT_EQ(m[0]["summary"]["not_done"], 2);
}

// Data maps only (skipped by their names, nothing converted): the merge's bookkeeping.
TEST(IngestRun, ShardManifestsMergeIntoTheBatchsAndAPartOfAnotherBatchIsRefused) {
  TempDir t;
  const fs::path lib = t.dir / "lib", out = t.dir / "out";
  for (const char* name : {"a_normal.png", "b_roughness.png", "c_mask.png", "walls/d_normal.png"})
    write_png(lib / name);
  std::ofstream(lib / "notes.txt") << "not an image";
  auto run_shard = [&](int shard) {
    IngestRequest r = request_for({lib.string()}, out.string());
    r.shard = shard;
    r.shards = 2;
    return run_ingest(plan_ingest(r), {}, kQuiet);
  };
  const IngestSummary a = run_shard(0), b = run_shard(1);
  EXPECT_EQ(a.files() + b.files(), 4u);
  const IngestSummary merged = merge_ingest_manifests(out.string());
  EXPECT_EQ(merged.skipped_data, 4u);
  EXPECT_EQ(merged.files(), 4u);
  EXPECT_EQ(merged.left_out, 1u);  // the .txt, counted once, not once per part
  EXPECT_EQ(merged.left_out_by_reason.at("not_image"), 1u);
  EXPECT_EQ(merged.manifest, (out / "spectralize-ingest.jsonl").string());
  const std::vector<Json> m = manifest_lines(merged.manifest);
  ASSERT_EQ(m.size(), 6u);  // four files, the .txt, the summary
  EXPECT_EQ(m.back()["summary"]["skipped_data"], 4);
  // The library changes and one shard runs again: its part is of another batch.
  write_png(lib / "e_mask.png");
  run_shard(1);
  test::expect_error_mentioning([&] { merge_ingest_manifests(out.string()); },
                                {"spectralize-ingest.part-", "another batch"}, "a stale part");
}

TEST(IngestRun, TheSummaryJsonHoldsEveryCountAndTheirTotal) {
  IngestSummary s;
  s.converted = 3;
  s.up_to_date = 2;
  s.skipped_data = 1;
  s.copied_data = 4;
  s.derived = 1;
  s.failed = 2;
  s.pixels = 1234;
  s.left_out = 5;
  s.not_entered = 1;
  s.left_out_by_reason = {{"hidden", 3}, {"not_image", 2}};
  s.manifest = "/lib/out/spectralize-ingest.jsonl";
  const Json j = Json::parse(ingest_summary_json(s));
  EXPECT_EQ(j["files"], 3 + 2 + 1 + 4 + 1 + 2);
  EXPECT_EQ(j["converted"], 3);
  EXPECT_EQ(j["up_to_date"], 2);
  EXPECT_EQ(j["skipped_data"], 1);
  EXPECT_EQ(j["copied_data"], 4);
  EXPECT_EQ(j["derived"], 1);
  EXPECT_EQ(j["failed"], 2);
  EXPECT_EQ(j["pixels"], 1234);
  EXPECT_EQ(j["left_out"], 5);
  EXPECT_EQ(j["not_entered"], 1);
  EXPECT_EQ(j["left_out_by_reason"]["hidden"], 3);
  EXPECT_EQ(j["manifest"], "/lib/out/spectralize-ingest.jsonl");
  EXPECT_FALSE(j.contains("interrupted"));  // said only when it happened
}

}  // namespace
}  // namespace spectralize
