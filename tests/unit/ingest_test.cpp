// Batch ingest (ingest/ingest.h) through its public functions on small libraries written here:
// the plan mirrors the source tree and names everything the walk leaves out, refuses requests
// that would ingest their own outputs, reads list files relative to the list; shards split a
// batch into disjoint parts that cover it, stable as files come and go, with one identity per
// batch; a run counts every file by status, a rerun converts only what changed (how a batch
// runs never makes its outputs stale), a stop before the start converts nothing and says so;
// shard manifests merge into the batch's and a part of another batch is refused. Oracles: the
// files each case writes, the documented name pattern ("{dir}/{stem}.exr") and manifest names,
// and the file system.

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

// A 4 x 4 8-bit RGB PNG of one colour (its folders made).
void write_png(const fs::path& path, unsigned char value = 120) {
  fs::create_directories(path.parent_path());
  const OIIO::ImageSpec spec(4, 4, 3, OIIO::TypeUInt8);
  std::vector<unsigned char> px(4 * 4 * 3, value);
  auto out = OIIO::ImageOutput::create(path.string());
  ASSERT_TRUE(out && out->open(path.string(), spec)) << OIIO::geterror();
  ASSERT_TRUE(out->write_image(OIIO::TypeUInt8, px.data()));
  ASSERT_TRUE(out->close());
}

IngestRequest request_for(std::vector<std::string> sources, const std::string& destination) {
  IngestRequest r;
  r.sources = std::move(sources);
  r.destination = destination;
  r.settings.threads = 2;
  return r;
}

// A path relative to `base`, as text ("walls/b.exr").
std::string relative_to(const std::string& path, const fs::path& base) {
  return fs::path(path).lexically_relative(base).generic_string();
}

// The outputs of a plan relative to its destination, by input relative to `source`.
std::map<std::string, std::string> outputs_of(const IngestPlan& plan, const fs::path& source) {
  std::map<std::string, std::string> out;
  for (const IngestItem& i : plan.items)
    out[relative_to(i.input, source)] = relative_to(i.output, plan.request.destination);
  return out;
}

// The kind of what the walk left out, by path relative to `source` ("" when not left out).
std::string left_out_kind(const IngestPlan& plan, const fs::path& source, const std::string& rel,
                          bool* failure = nullptr) {
  for (const LeftOut& l : plan.left_out)
    if (relative_to(l.path, source) == rel) {
      if (failure) *failure = l.failure;
      return l.kind;
    }
  return "";
}

std::vector<Json> manifest_lines(const std::string& path) {
  std::vector<Json> out;
  std::ifstream f(path);
  for (std::string line; std::getline(f, line);) out.push_back(Json::parse(line));
  return out;
}

// --- Planning ---

TEST(IngestPlan, TheOutputsMirrorTheTreeAndTheWalkNamesWhatItLeavesOut) {
  TempDir t;
  const fs::path lib = t.dir / "lib";
  write_png(lib / "a_basecolor.png");
  write_png(lib / "walls/b_basecolor.png");
  write_png(lib / "walls/deep/c.png");
  std::ofstream(lib / "notes.txt") << "not an image";
  write_png(lib / ".hidden.png");
  std::ofstream(lib / "walls/.c.exr.spectralize-AbC123.tmp") << "a killed run's";
  fs::create_symlink(lib / "nowhere.png", lib / "dangling.png");
  fs::create_symlink(lib, lib / "walls/loop");             // back to an ancestor
  fs::create_symlink(lib / "walls", lib / "z_walls_too");  // a folder walked before
  // The library, and one of its files again by another spelling.
  const IngestPlan plan = plan_ingest(request_for(
      {lib.string(), (lib / "walls/../a_basecolor.png").string()}, (t.dir / "out").string()));
  EXPECT_EQ(outputs_of(plan, lib),
            (std::map<std::string, std::string>{{"a_basecolor.png", "a_basecolor.exr"},
                                                {"walls/b_basecolor.png", "walls/b_basecolor.exr"},
                                                {"walls/deep/c.png", "walls/deep/c.exr"}}));
  for (const IngestItem& i : plan.items) {
    EXPECT_EQ(i.relative, relative_to(i.output, t.dir / "out"));
    EXPECT_EQ(i.source_relative, relative_to(i.input, lib));
    EXPECT_TRUE(i.failure.empty()) << i.failure;
  }
  EXPECT_EQ(plan.all_items, 3u);
  EXPECT_EQ(plan.manifest, (t.dir / "out/spectralize-ingest.jsonl").string());
  bool failure = true;
  EXPECT_EQ(left_out_kind(plan, lib, "notes.txt", &failure), "not_image");
  EXPECT_FALSE(failure);
  EXPECT_EQ(left_out_kind(plan, lib, ".hidden.png"), "hidden");
  EXPECT_EQ(left_out_kind(plan, lib, "walls/.c.exr.spectralize-AbC123.tmp"), "temporary");
  EXPECT_EQ(left_out_kind(plan, lib, "dangling.png", &failure), "dangling_link");
  EXPECT_FALSE(failure);
  EXPECT_EQ(left_out_kind(plan, lib, "z_walls_too", &failure), "same_folder");
  EXPECT_FALSE(failure);
  // A loop is a failure of the walk (the batch exits 1): it could not do its job there.
  EXPECT_EQ(left_out_kind(plan, lib, "walls/loop", &failure), "loop");
  EXPECT_TRUE(failure);
  EXPECT_EQ(left_out_kind(plan, lib, "walls/../a_basecolor.png"), "duplicate");
}

TEST(IngestPlan, RequestsThatWouldIngestTheirOwnOutputsAreRefused) {
  TempDir t;
  const fs::path lib = t.dir / "lib";
  write_png(lib / "walls/a.png");
  // The destination inside a source folder, or where a pattern looks: a command-line mistake
  // (Error, exit 2), never a FileError.
  auto refused = [](const IngestRequest& r, std::vector<std::string> words) {
    try {
      plan_ingest(r);
      ADD_FAILURE() << "accepted";
    } catch (const FileError& e) {
      ADD_FAILURE() << "a FileError: " << e.what();
    } catch (const Error& e) {
      for (const std::string& w : words)
        EXPECT_NE(std::string(e.what()).find(w), std::string::npos) << e.what() << " lacks " << w;
    }
  };
  refused(request_for({lib.string()}, (lib / "out").string()),
          {"'" + (lib / "out").string() + "'", "inside the source folder"});
  refused(request_for({(lib / "*/*.png").string()}, (lib / "spectral").string()),
          {"'" + (lib / "spectral").string() + "'", "looks for files"});
  IngestRequest shard = request_for({lib.string()}, (t.dir / "out").string());
  shard.shard = 2;
  shard.shards = 2;
  refused(shard, {"shard 2/2"});
  fs::create_directories(t.dir / "empty");
  refused(request_for({(t.dir / "empty").string()}, (t.dir / "out").string()),
          {"no input files found"});
  // A destination that is a file: the file system's refusal (FileError, exit 1).
  std::ofstream(t.dir / "blocker") << "a file";
  test::expect_error_mentioning(
      [&] { plan_ingest(request_for({lib.string()}, (t.dir / "blocker").string())); },
      {"blocker", "is not a folder"}, "a file as the destination");
  EXPECT_FALSE(fs::exists(lib / "out"));
  EXPECT_FALSE(fs::exists(lib / "spectral"));
}

TEST(IngestPlan, ListLinesAreRelativeToTheListAndMayCarryTheirOwnSettings) {
  TempDir t;
  const fs::path lib = t.dir / "lib";
  write_png(lib / "a.png");
  write_png(lib / "sky/b.png");
  std::ofstream(lib / "list.txt")
      << "# two files\n\na.png\n"
         "{\"input\": \"sky/b.png\", \"wavelengths\": \"400:700:10\"}\n";
  IngestRequest r = request_for({}, (t.dir / "out").string());
  r.inputs_from = (lib / "list.txt").string();
  const IngestPlan plan = plan_ingest(r);
  ASSERT_EQ(plan.items.size(), 2u);
  EXPECT_EQ(outputs_of(plan, lib),
            (std::map<std::string, std::string>{{"a.png", "a.exr"}, {"sky/b.png", "sky/b.exr"}}));
  for (const IngestItem& i : plan.items) {
    const bool b = i.input.find("b.png") != std::string::npos;
    EXPECT_EQ(i.settings.spectral.grid.size(), b ? 31u : 81u)
        << i.input;  // 400:700:10, or 380:780:5
  }
  // A malformed line is named.
  std::ofstream(lib / "bad.txt") << "a.png\n{\"input\": 3}\n";
  r.inputs_from = (lib / "bad.txt").string();
  test::expect_error_mentioning([&] { plan_ingest(r); }, {"bad.txt", "line 2"}, "a bad line");
}

// --- Shards ---

TEST(IngestPlan, ShardsAreDisjointPartsThatCoverTheBatchStableAsFilesComeAndGo) {
  TempDir t;
  const fs::path lib = t.dir / "lib";
  for (int i = 0; i < 12; ++i)
    write_png(lib / (i % 2 ? "walls" : "floors") / ("tile" + std::to_string(i) + ".png"));
  const std::string out = (t.dir / "out").string();
  auto plan_of = [&](int shard, int shards) {
    IngestRequest r = request_for({lib.string()}, out);
    r.shard = shard;
    r.shards = shards;
    return plan_ingest(r);
  };
  auto split = [&](int shards) {
    std::vector<std::set<std::string>> parts;
    std::set<std::string> batches;
    for (int k = 0; k < shards; ++k) {
      const IngestPlan p = plan_of(k, shards);
      std::set<std::string> part;
      for (const IngestItem& i : p.items) part.insert(i.relative);
      parts.push_back(part);
      batches.insert(p.batch);
      EXPECT_EQ(p.manifest, out + "/spectralize-ingest.part-" + std::to_string(k) + "-of-" +
                                std::to_string(shards) + ".jsonl");
    }
    EXPECT_EQ(batches.size(), 1u) << "the shards of one batch disagree on its identity";
    return std::pair{parts, *batches.begin()};
  };
  std::set<std::string> all;
  for (const IngestItem& i : plan_of(0, 1).items) all.insert(i.relative);
  ASSERT_EQ(all.size(), 12u);
  const auto [parts, batch] = split(3);
  std::set<std::string> together;
  std::size_t sizes = 0;
  for (const auto& part : parts) {
    EXPECT_LT(part.size(), 12u);  // a split, not everything in one
    sizes += part.size();
    together.insert(part.begin(), part.end());
  }
  EXPECT_EQ(sizes, 12u);  // disjoint
  EXPECT_EQ(together, all);
  // A new file takes its place; every other file stays in its shard. The batch is another.
  write_png(lib / "walls/tile12.png");
  const auto [grown, grown_batch] = split(3);
  for (int k = 0; k < 3; ++k) {
    std::set<std::string> without = grown[k];
    without.erase("walls/tile12.exr");
    EXPECT_EQ(without, parts[k]) << "shard " << k;
  }
  EXPECT_NE(grown_batch, batch);
}

TEST(IngestPlan, TheBatchIdentityFollowsWhatShapesTheFilesNotHowTheBatchRuns) {
  TempDir t;
  const fs::path lib = t.dir / "lib";
  write_png(lib / "a.png");
  write_png(lib / "b.png");
  const IngestRequest base = request_for({lib.string()}, (t.dir / "out").string());
  const std::string batch = plan_ingest(base).batch;
  IngestRequest faster = base;
  faster.settings.threads = 1;
  faster.settings.ingest.jobs = 3;
  EXPECT_EQ(plan_ingest(faster).batch, batch);
  IngestRequest other = base;
  other.settings.spectral.grid = WavelengthGrid(400, 700, 10);
  EXPECT_NE(plan_ingest(other).batch, batch);
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
