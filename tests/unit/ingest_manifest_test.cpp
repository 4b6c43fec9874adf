// An ingest manifest's records and the merge of a farm's parts (ingest/ingest_manifest.h,
// ingest/ingest.h; docs/DESIGN.md §12): the summary line holds every count, their total and the
// part's identity (shard, or merged); a left-out record names the path, kind, reason and
// failure; names that are not UTF-8 are written as valid JSON and read back with their bytes.
// Parts written here merge into one manifest holding every file record once, the walk's
// account once, and a summary of the sums; a corrupt, incomplete, renamed, missing, duplicated
// or foreign part is refused naming it, and nothing is written then. Oracles: the records and
// counts each case writes, base64 (RFC 4648) of the bytes worked out by hand, the documented
// part names ("spectralize-ingest.part-I-of-N.jsonl") and the file system.

#include "ingest/ingest_manifest.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "file_test_support.h"
#include "ingest/shard.h"
#include "spectralize/core/error.h"
#include "test_support.h"
#include "text/json_text.h"

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

namespace spectralize {
namespace {

struct TempDir : test::TempDir {
  TempDir() : test::TempDir("ingest_manifest") {}
};

constexpr const char* kBatch = "0123456789abcdef";

// A name that is not UTF-8 (two stray bytes), and a valid name that spells its escaped text:
// only their bytes tell them apart.
const std::string kStray = "lib/\xff\xfe.png";
const std::string kLookalike = "lib/\\xFF\\xFE.png";
const std::string kStrayBase64 = "bGliL//+LnBuZw==";  // base64 of the bytes of kStray

// A file's record as run_ingest writes one: its input (by json_text.h), status and pixels.
Json file_record(const std::string& input, const std::string& status, std::uint64_t pixels = 0) {
  Json j;
  put_path(j, "input", input);
  j["status"] = status;
  if (pixels) j["pixels"] = pixels;
  return j;
}

struct PartText {
  std::vector<Json> files;
  std::vector<LeftOut> left_out;
  IngestSummary summary;  // its counts; files() must match `files` unless a case says otherwise
};

// Writes part `index` of `count` of the batch into `dir`: its records, then its summary line.
std::string write_part(const fs::path& dir, int index, int count, const PartText& p,
                       std::uint64_t batch_files, const std::string& batch = kBatch) {
  const std::string path = (dir / part_name({index, count})).string();
  std::ofstream f(path);
  for (const Json& r : p.files) f << dump_json(r) << "\n";
  for (const LeftOut& l : p.left_out) f << left_out_line(l) << "\n";
  f << summary_line(p.summary, PartInfo{batch, {index, count}, batch_files, false}) << "\n";
  return path;
}

std::vector<Json> lines_of(const std::string& path) {
  std::vector<Json> out;
  std::ifstream f(path);
  for (std::string line; std::getline(f, line);) out.push_back(Json::parse(line));
  return out;
}

// Three parts of a batch of six files, with the walk's account (the same in every part).
void write_batch(const fs::path& dir) {
  fs::create_directories(dir);
  const std::vector<LeftOut> walk = {{"lib/notes.txt", "not_image", "not an image", false},
                                     {"lib/locked", "unreadable_folder", "cannot be read", true}};
  PartText a, b, c;
  a.files = {file_record("lib/a.png", "converted", 16), file_record(kStray, "converted", 64)};
  a.summary.converted = 2;
  a.summary.pixels = 80;
  a.summary.seconds = 1.5;
  a.summary.stale_temporaries_removed = 1;
  b.files = {file_record(kLookalike, "up_to_date"), file_record("lib/n_normal.png", "skipped_data"),
             file_record("lib/bad.png", "failed")};
  b.summary.up_to_date = 1;
  b.summary.skipped_data = 1;
  b.summary.failed = 1;
  b.summary.seconds = 4.25;
  c.files = {file_record("lib/m_mask.png", "copied_data")};
  c.summary.copied_data = 1;
  c.summary.seconds = 0.5;
  c.summary.stale_temporaries_removed = 2;
  for (PartText* p : {&a, &b, &c}) {
    p->left_out = walk;
    p->summary.left_out = 2;
    p->summary.not_entered = 1;
  }
  write_part(dir, 0, 3, a, 6);
  write_part(dir, 1, 3, b, 6);
  write_part(dir, 2, 3, c, 6);
}

TEST(IngestManifest, TheSummaryLineHoldsEveryCountTheirTotalAndThePartsIdentity) {
  IngestSummary s;
  s.converted = 3;
  s.up_to_date = 2;
  s.skipped_data = 1;
  s.copied_data = 4;
  s.derived = 5;
  s.failed = 2;
  s.pixels = 1234;
  s.stale_temporaries_removed = 6;
  s.left_out = 7;
  s.not_entered = 1;
  s.left_out_by_reason = {{"hidden", 4}, {"not_image", 3}};
  s.seconds = 2.5;
  const std::string line = summary_line(s, PartInfo{kBatch, {1, 3}, 40, false});
  EXPECT_EQ(line.find('\n'), std::string::npos);  // one line of JSON Lines
  const Json j = Json::parse(line);
  ASSERT_TRUE(j.contains("summary"));
  const Json& m = j["summary"];
  EXPECT_EQ(m["files"], 3 + 2 + 1 + 4 + 5 + 2);
  const std::map<std::string, int> counts = {
      {"converted", 3}, {"up_to_date", 2}, {"skipped_data", 1}, {"copied_data", 4},
      {"derived", 5},   {"failed", 2},     {"pixels", 1234},    {"stale_temporaries_removed", 6},
      {"left_out", 7},  {"not_entered", 1}};
  for (const auto& [key, n] : counts) EXPECT_EQ(m[key], n) << key;
  EXPECT_EQ(m["left_out_by_reason"], (Json{{"hidden", 4}, {"not_image", 3}}));
  EXPECT_EQ(m["seconds"], 2.5);
  EXPECT_EQ(m["batch"], kBatch);
  EXPECT_EQ(m["shard"], 1);
  EXPECT_EQ(m["shards"], 3);
  EXPECT_EQ(m["batch_files"], 40);
  EXPECT_FALSE(m.contains("merged"));
  EXPECT_FALSE(m.contains("interrupted"));  // said only when it happened
  // The merge of all parts: marked merged, no shard of its own. An interruption is said.
  s.interrupted = true;
  s.not_done = 9;
  const Json merged = Json::parse(summary_line(s, PartInfo{kBatch, {0, 3}, 40, true}))["summary"];
  EXPECT_EQ(merged["merged"], true);
  EXPECT_FALSE(merged.contains("shard"));
  EXPECT_EQ(merged["shards"], 3);
  EXPECT_EQ(merged["interrupted"], true);
  EXPECT_EQ(merged["not_done"], 9);
}

TEST(IngestManifest, NamesThatAreNotUtf8AreValidJsonAndKeepTheirBytes) {
  // A left-out record: the path readable (\xNN) and its bytes in base64; the reason escaped.
  const std::string line =
      left_out_line({kStray, "not_image", std::string("not an image: \xff"), true});
  const Json j = Json::parse(line);  // valid JSON (nlohmann refuses invalid UTF-8)
  EXPECT_EQ(j["left_out"], "lib/\\xFF\\xFE.png");
  EXPECT_EQ(j["left_out_base64"], kStrayBase64);
  EXPECT_EQ(path_from(j, "left_out"), kStray);
  EXPECT_EQ(j["kind"], "not_image");
  EXPECT_EQ(j["reason"], "not an image: \\xFF");
  EXPECT_EQ(j["failure"], true);
  // A valid name is written as it is, without base64.
  const Json valid = Json::parse(left_out_line({"lib/été.png", "hidden", "a hidden file", false}));
  EXPECT_EQ(valid["left_out"], "lib/été.png");
  EXPECT_FALSE(valid.contains("left_out_base64"));
  EXPECT_EQ(valid["failure"], false);
  // The summary JSON's manifest path likewise.
  IngestSummary s;
  s.manifest = "/out/\xff/spectralize-ingest.jsonl";
  const Json summary = Json::parse(ingest_summary_json(s));
  EXPECT_EQ(path_from(summary, "manifest"), s.manifest);
  EXPECT_EQ(summary["files"], 0);
}

TEST(IngestManifest, PartsMergeIntoOneManifestOfEveryRecordOnceAndTheSums) {
  TempDir t;
  write_batch(t.dir);
  const IngestSummary m = merge_ingest_manifests(t.dir.string());
  EXPECT_EQ(m.manifest, (t.dir / "spectralize-ingest.jsonl").string());
  EXPECT_EQ(m.files(), 6u);
  EXPECT_EQ(m.converted, 2u);
  EXPECT_EQ(m.up_to_date, 1u);
  EXPECT_EQ(m.skipped_data, 1u);
  EXPECT_EQ(m.copied_data, 1u);
  EXPECT_EQ(m.failed, 1u);
  EXPECT_EQ(m.pixels, 80u);                    // the converted files' pixels
  EXPECT_EQ(m.seconds, 4.25);                  // the parts ran side by side: the longest
  EXPECT_EQ(m.stale_temporaries_removed, 3u);  // each part removed its own
  // The walk's account, once (every part saw the same walk), its failure counted.
  EXPECT_EQ(m.left_out, 2u);
  EXPECT_EQ(m.not_entered, 1u);
  EXPECT_EQ(m.left_out_by_reason,
            (std::map<std::string, std::uint64_t>{{"not_image", 1}, {"unreadable_folder", 1}}));
  EXPECT_FALSE(m.ok());
  // Read back: every file record once with its bytes, the account once, the summary last.
  const std::vector<Json> lines = lines_of(m.manifest);
  ASSERT_EQ(lines.size(), 6u + 2u + 1u);
  std::multiset<std::string> inputs;
  std::size_t left = 0;
  for (std::size_t i = 0; i + 1 < lines.size(); ++i) {
    if (lines[i].contains("left_out")) {
      ++left;
      continue;
    }
    inputs.insert(path_from(lines[i], "input"));
  }
  EXPECT_EQ(left, 2u);
  EXPECT_EQ(inputs, (std::multiset<std::string>{"lib/a.png", kStray, kLookalike, "lib/n_normal.png",
                                                "lib/bad.png", "lib/m_mask.png"}));
  const Json& s = lines.back()["summary"];
  EXPECT_EQ(s["files"], 6);
  EXPECT_EQ(s["converted"], 2);
  EXPECT_EQ(s["merged"], true);
  EXPECT_EQ(s["shards"], 3);
  EXPECT_EQ(s["batch"], kBatch);
  EXPECT_EQ(s["batch_files"], 6);
  // The parts stay; merging again gives the same manifest.
  EXPECT_TRUE(fs::exists(t.dir / part_name({0, 3})));
  std::ifstream first(m.manifest);
  const std::string before{std::istreambuf_iterator<char>(first), {}};
  merge_ingest_manifests(t.dir.string());
  std::ifstream second(m.manifest);
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(second), {}), before);
}

// Expects the merge of `dir` to be refused with a FileError mentioning `words`, writing nothing.
void expect_refused(const fs::path& dir, std::vector<std::string> words, const std::string& what) {
  SCOPED_TRACE(what);
  try {
    merge_ingest_manifests(dir.string());
    ADD_FAILURE() << "merged";
  } catch (const FileError& e) {
    for (const std::string& w : words)
      EXPECT_NE(std::string(e.what()).find(w), std::string::npos) << e.what() << " lacks " << w;
  } catch (const std::exception& e) {
    ADD_FAILURE() << "not a FileError: " << e.what();
  }
  EXPECT_FALSE(fs::exists(dir / "spectralize-ingest.jsonl"));
}

// A batch of two parts of one file each, then `edit` applied to the text of part 1.
void write_pair(const fs::path& dir, const std::function<std::string(std::string)>& edit) {
  fs::create_directories(dir);
  PartText a, b;
  a.files = {file_record("lib/a.png", "converted", 16)};
  a.summary.converted = 1;
  b.files = {file_record("lib/b.png", "converted", 16)};
  b.summary.converted = 1;
  write_part(dir, 0, 2, a, 2);
  const std::string path = write_part(dir, 1, 2, b, 2);
  std::ifstream in(path);
  const std::string text{std::istreambuf_iterator<char>(in), {}};
  in.close();
  std::ofstream(path) << edit(text);
}

TEST(IngestManifest, ACorruptOrIncompletePartIsRefusedNamingItAndTheLine) {
  TempDir t;
  const std::string part1 = part_name({1, 2});
  const auto summary_at = [](const std::string& text) { return text.find("{\"summary\""); };
  struct Case {
    std::string name;
    std::function<std::string(std::string)> edit;
    std::vector<std::string> words;
  };
  const std::vector<Case> cases = {
      {"cut mid-record",
       [](std::string s) { return s.substr(0, s.size() / 2); },
       {part1, "line 2", "not a JSON object"}},
      {"not JSON",
       [](std::string s) { return "this is not JSON\n" + s; },
       {part1, "line 1", "not a JSON object"}},
      {"a JSON array", [](std::string s) { return "[1, 2]\n" + s; }, {part1, "line 1"}},
      {"neither",
       [](std::string s) { return "{\"x\": 1}\n" + s; },
       {part1, "line 1", "neither a file's record nor a summary"}},
      {"after the summary",
       [](std::string s) { return s + "{\"input\": \"c\", \"status\": \"failed\"}\n"; },
       {part1, "line 3", "records after the summary"}},
      {"no summary",
       [&](std::string s) { return s.substr(0, summary_at(s)); },
       {part1, "no summary record"}},
      {"empty", [](std::string) { return std::string(); }, {part1, "is empty"}},
      {"no batch",
       [](std::string s) {
         const auto at = s.find("\"batch\":");
         return s.replace(at, 8, "\"butch\":");
       },
       {part1, "names no batch"}},
      {"renamed",
       [](std::string s) {
         const auto at = s.find("\"shard\":1");
         return s.replace(at, 9, "\"shard\":0");
       },
       {part1, "shard 0 of 2", "renamed?"}},
      {"a record short",
       [](std::string s) {
         const std::size_t end = s.find('\n');  // the file record's line, dropped
         return end == std::string::npos ? s : s.substr(end + 1);
       },
       {part1, "0 file records", "says 1", "cut short?"}},
      {"another batch",
       [](std::string s) {
         const auto at = s.find(kBatch);
         return s.replace(at, 16, "fedcba9876543210");
       },
       {part1, "another batch", "fedcba9876543210", part_name({0, 2})}},
      {"an input twice",
       [](std::string s) {
         const auto at = s.find("lib/b.png");
         return s.replace(at, 9, "lib/a.png");
       },
       {"lib/a.png", "in two parts"}},
      {"a batch of more files",
       [](std::string s) {
         const auto at = s.find("\"batch_files\":2");
         return s.replace(at, 15, "\"batch_files\":3");
       },
       {part_name({0, 2}), "another batch"}},
  };
  int n = 0;
  for (const Case& c : cases) {
    const fs::path dir = t.dir / std::to_string(n++);
    write_pair(dir, c.edit);
    expect_refused(dir, c.words, c.name);
  }
}

TEST(IngestManifest, MissingStaleMisnamedOrNonFileMembersOfABatchAreRefused) {
  TempDir t;
  // Shard 1 of 3 missing.
  const fs::path gap = t.dir / "gap";
  write_batch(gap);
  fs::remove(gap / part_name({1, 3}));
  expect_refused(gap, {"shards 1 of 3", "missing"}, "a missing shard");
  // A part of a run of another shard count left beside them.
  const fs::path mixed = t.dir / "mixed";
  write_batch(mixed);
  std::ofstream(mixed / part_name({0, 2})) << "stale\n";
  // (Which count is named first depends on the order the folder lists them.)
  expect_refused(mixed, {"manifest parts of", "shards", "remove the stale ones"},
                 "parts of two runs");
  // A name that claims to be a part and is not exactly one.
  const fs::path misnamed = t.dir / "misnamed";
  write_batch(misnamed);
  std::ofstream(misnamed / "spectralize-ingest.part-03-of-3.jsonl") << "\n";
  expect_refused(misnamed, {"spectralize-ingest.part-03-of-3.jsonl"}, "a misnamed part");
  // A part that is a folder.
  const fs::path folder = t.dir / "folder";
  write_batch(folder);
  fs::remove(folder / part_name({2, 3}));
  fs::create_directories(folder / part_name({2, 3}));
  expect_refused(folder, {part_name({2, 3}), "not a regular file"}, "a folder as a part");
  // Other names in the folder are not parts: the merge goes on without them.
  const fs::path others = t.dir / "others";
  write_batch(others);
  std::ofstream(others / "notes.jsonl") << "not a part\n";
  std::ofstream(others / "spectralize-ingest.jsonl.bak") << "not a part\n";
  EXPECT_EQ(merge_ingest_manifests(others.string()).files(), 6u);
  // No parts at all, a missing destination, a file as the destination.
  fs::create_directories(t.dir / "empty");
  expect_refused(t.dir / "empty", {"no manifest parts to merge"}, "no parts");
  expect_refused(t.dir / "nowhere", {"nowhere", "no such folder"}, "a missing folder");
  std::ofstream(t.dir / "a_file") << "x";
  try {
    merge_ingest_manifests((t.dir / "a_file").string());
    ADD_FAILURE() << "a file merged into";
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find("is not a folder"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace spectralize
