// An ingest manifest's records and the merge of a farm's parts into one (docs/DESIGN.md §12).

#include "ingest/ingest_manifest.h"

#include <sys/stat.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>

#include "imagefile/safe_output.h"
#include "spectralize/core/error.h"
#include "text/json_text.h"
#include "text/strings.h"

namespace fs = std::filesystem;

namespace spectralize {

namespace {

using Json = nlohmann::ordered_json;

constexpr const char* kManifestName = "spectralize-ingest.jsonl";

Json counts_json(const IngestSummary& s) {
  Json j;
  j["files"] = s.files();
  j["converted"] = s.converted;
  j["up_to_date"] = s.up_to_date;
  j["skipped_data"] = s.skipped_data;
  j["copied_data"] = s.copied_data;
  j["derived"] = s.derived;
  j["failed"] = s.failed;
  j["pixels"] = s.pixels;
  j["stale_temporaries_removed"] = s.stale_temporaries_removed;
  j["left_out"] = s.left_out;
  j["not_entered"] = s.not_entered;
  j["left_out_by_reason"] = Json::object();
  for (const auto& [kind, n] : s.left_out_by_reason) j["left_out_by_reason"][kind] = n;
  j["seconds"] = s.seconds;
  j["work"] = {{"configs_parsed", s.work.configs_parsed},
               {"spectralizers_built", s.work.spectralizers_built},
               {"file_rule_matches", s.work.file_rule_matches},
               {"inputs_opened", s.work.inputs_opened}};
  if (s.interrupted) {
    j["interrupted"] = true;
    j["not_done"] = s.not_done;
  }
  return j;
}

// The statuses of file records, counted into `s`.
void count(IngestSummary& s, const std::string& status, std::uint64_t pixels) {
  if (status == "converted") ++s.converted, s.pixels += pixels;
  if (status == "up_to_date") ++s.up_to_date;
  if (status == "skipped_data") ++s.skipped_data;
  if (status == "copied_data") ++s.copied_data;
  if (status == "derived") ++s.derived;
  if (status == "failed") ++s.failed;
}

// A part of a batch as read back: its records and its summary.
struct Part {
  std::string path;
  ShardSpec shard;
  std::vector<Json> files, left_out;
  Json summary;
};

Part read_part(const fs::path& path, const ShardSpec& shard) {
  Part p{path.string(), shard, {}, {}, {}};
  const std::string where = quoted_path(p.path);
  struct stat st = {};
  if (::stat(path.c_str(), &st) != 0) throw FileError(where + ": " + std::strerror(errno));
  if (!S_ISREG(st.st_mode))
    throw FileError(where + ": is not a regular file (a manifest part is one)");
  check_readable_file(p.path, "a manifest part");
  std::ifstream f(path);
  std::string line;
  int number = 0;
  for (; std::getline(f, line); ++number) {
    if (!p.summary.is_null())
      throw FileError(where + " line " + std::to_string(number + 1) +
                      ": records after the summary (a part is one run's)");
    Json r = Json::parse(line, nullptr, false);
    if (r.is_discarded() || !r.is_object())
      throw FileError(where + " line " + std::to_string(number + 1) + ": not a JSON object");
    if (r.contains("summary"))
      p.summary = r["summary"];
    else if (r.contains("left_out"))
      p.left_out.push_back(std::move(r));
    else if (r.contains("status") && r["status"].is_string())
      p.files.push_back(std::move(r));
    else
      throw FileError(where + " line " + std::to_string(number + 1) +
                      ": neither a file's record nor a summary");
  }
  if (f.bad()) throw FileError(where + ": cannot be read to the end");
  if (number == 0) throw FileError(where + ": is empty (did that task finish?)");
  if (p.summary.is_null() || !p.summary.is_object())
    throw FileError(where + ": has no summary record at its end (did that task finish?)");
  const Json& s = p.summary;
  if (!s.contains("batch") || !s["batch"].is_string() || !s.contains("shard") ||
      !s.contains("shards") || !s["shard"].is_number_unsigned() ||
      !s["shards"].is_number_unsigned() || !s.contains("batch_files"))
    throw FileError(where +
                    ": its summary names no batch (written by an older spectralize? "
                    "rerun that shard)");
  if (s["shard"].get<std::uint64_t>() != static_cast<std::uint64_t>(shard.index) ||
      s["shards"].get<std::uint64_t>() != static_cast<std::uint64_t>(shard.count))
    throw FileError(where + ": its summary says shard " + s["shard"].dump() + " of " +
                    s["shards"].dump() + ", its name " + std::to_string(shard.index) + " of " +
                    std::to_string(shard.count) + " (renamed?)");
  if (!s.contains("files") || s["files"] != p.files.size())
    throw FileError(where + ": holds " + std::to_string(p.files.size()) +
                    " file records, its summary says " + s.value("files", Json()).dump() +
                    " (cut short?)");
  return p;
}

}  // namespace

std::string summary_line(const IngestSummary& summary, const PartInfo& part) {
  Json j = counts_json(summary);
  j["batch"] = part.batch;
  if (part.merged)
    j["merged"] = true;
  else
    j["shard"] = part.shard.index;
  j["shards"] = part.shard.count;
  j["batch_files"] = part.batch_files;
  return dump_json(Json{{"summary", j}});
}

std::string left_out_line(const LeftOut& left) {
  Json j;
  put_path(j, "left_out", left.path);
  j["kind"] = left.kind;
  j["reason"] = utf8_escaped(left.reason);
  j["failure"] = left.failure;
  return dump_json(j);
}

std::string ingest_summary_json(const IngestSummary& summary) {
  Json j = counts_json(summary);
  put_path(j, "manifest", summary.manifest);
  return dump_json(j);
}

IngestSummary merge_ingest_manifests(const std::string& destination) {
  const ReadFileScope reads;  // no output of the merge replaces a part it reads
  const std::string where = quoted_path(destination);
  std::error_code ec;
  if (!fs::is_directory(destination, ec))
    throw FileError(where + ": " +
                    (fs::exists(destination, ec) ? "is not a folder" : "no such folder"));
  // Every name that claims to be a part must be one; each shard once.
  std::map<int, std::pair<fs::path, ShardSpec>> named;
  int shards = 0;
  for (fs::directory_iterator it(destination, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    std::optional<ShardSpec> shard;
    try {
      shard = parse_part_name(name);
    } catch (const Error& e) {
      throw FileError(where + ": " + e.what());
    }
    if (!shard) continue;
    if (shards && shard->count != shards)
      throw FileError(where + ": manifest parts of " + std::to_string(shards) + " and of " +
                      std::to_string(shard->count) + " shards ('" + name +
                      "'); remove the stale ones");
    shards = shard->count;
    named[shard->index] = {it->path(), *shard};
  }
  if (ec) throw FileError(where + ": " + ec.message());
  if (!shards) throw FileError(where + ": no manifest parts to merge");
  std::string missing;
  for (int i = 0; i < shards; ++i)
    if (!named.count(i)) missing += (missing.empty() ? "" : ", ") + std::to_string(i);
  if (!missing.empty())
    throw FileError(where + ": the manifests of shards " + clip(missing, 200) + " of " +
                    std::to_string(shards) + " are missing (did those tasks finish?)");
  std::vector<Part> parts;
  for (const auto& [i, entry] : named) parts.push_back(read_part(entry.first, entry.second));
  // One batch: the same identity and file count in every part.
  const std::string batch = parts[0].summary["batch"].get<std::string>();
  const Json batch_files = parts[0].summary["batch_files"];
  for (const Part& p : parts)
    if (p.summary["batch"] != batch || p.summary["batch_files"] != batch_files)
      throw FileError(quoted_path(p.path) + " is a part of another batch (" +
                      p.summary["batch"].dump() + ", " + p.summary["batch_files"].dump() +
                      " files) than " + quoted_path(parts[0].path) + " (\"" + batch + "\", " +
                      batch_files.dump() +
                      " files): a stale part of an earlier run, or the library changed "
                      "between tasks; rerun the stale shards");
  // Together every file once.
  IngestSummary sum;
  std::set<std::string> inputs;
  std::string text;
  for (const Part& p : parts) {
    for (const Json& r : p.files) {
      const std::string input = path_from(r, "input");
      if (!inputs.insert(input).second)
        throw FileError(quoted_path(p.path) + ": " + quoted_path(input) +
                        " is in two parts of the batch");
      count(sum, r["status"].get<std::string>(), r.value("pixels", std::uint64_t{0}));
      text += dump_json(r) + "\n";
    }
    sum.seconds = std::max(sum.seconds, p.summary.value("seconds", 0.0));
    sum.stale_temporaries_removed += p.summary.value("stale_temporaries_removed", 0);
    const Json work = p.summary.value("work", Json::object());
    sum.work.configs_parsed += work.value("configs_parsed", std::uint64_t{0});
    sum.work.spectralizers_built += work.value("spectralizers_built", std::uint64_t{0});
    sum.work.file_rule_matches += work.value("file_rule_matches", std::uint64_t{0});
    sum.work.inputs_opened += work.value("inputs_opened", std::uint64_t{0});
  }
  if (!batch_files.is_number_unsigned() || sum.files() != batch_files.get<std::uint64_t>())
    throw FileError(where + ": the parts hold " + std::to_string(sum.files()) +
                    " files of a batch of " + batch_files.dump());
  // What the walk left out: every part saw the same walk; the first part's account.
  for (const Json& l : parts[0].left_out) {
    text += dump_json(l) + "\n";
    ++sum.left_out;
    ++sum.left_out_by_reason[l.value("kind", std::string("other"))];
    if (l.value("failure", false)) ++sum.not_entered;
  }
  sum.manifest = (fs::path(destination) / kManifestName).string();
  text += summary_line(sum, PartInfo{batch, {0, shards}, sum.files(), true}) + "\n";
  AtomicOutput out(sum.manifest, WriteRules::named("the merged manifest").below(destination));
  out.write(text);
  out.commit();
  return sum;
}

}  // namespace spectralize
