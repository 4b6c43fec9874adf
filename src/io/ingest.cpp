#include "io/ingest.h"

#include <OpenImageIO/imageio.h>
#include <fcntl.h>
#include <glob.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cinttypes>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>
#include <sstream>
#include <thread>

#include "core/error.h"
#include "io/colour_space.h"
#include "io/exr_header.h"
#include "io/image_input.h"
#include "io/image_job.h"
#include "io/input_interpretation.h"
#include "io/map_kind.h"
#include "io/safe_output.h"
#include "io/same_stem.h"
#include "io/table_pool.h"

namespace fs = std::filesystem;

namespace spectralize {

namespace {

using Json = nlohmann::ordered_json;
using Clock = std::chrono::steady_clock;

constexpr const char* kKeyAttribute = "spectralize:ingestKey";
constexpr const char* kManifestName = "spectralize-ingest.jsonl";

std::uint64_t fnv1a(std::string_view s) {
  std::uint64_t h = 1469598103934665603ull;
  for (unsigned char c : s) h = (h ^ c) * 1099511628211ull;
  return h;
}

std::string hex(std::uint64_t v) {
  char buf[24];
  std::snprintf(buf, sizeof buf, "%016" PRIx64, v);
  return buf;
}

std::string quoted_path(const std::string& p) {
  return "'" + clip(p, 200) + "'";
}

// The extensions OIIO reads ("exr", "png", ...), lower case.
const std::set<std::string>& image_extensions() {
  static const std::set<std::string> extensions = [] {
    std::set<std::string> out;
    std::string list;
    OIIO::getattribute("extension_list", list);  // "openexr:exr,sxr;png:png;..."
    for (const auto& format : OIIO::Strutil::splits(list, ";")) {
      const auto colon = format.find(':');
      if (colon == std::string::npos) continue;
      for (const auto& ext : OIIO::Strutil::splits(format.substr(colon + 1), ","))
        out.insert(OIIO::Strutil::lower(ext));
    }
    return out;
  }();
  return extensions;
}

bool is_image_name(const fs::path& p) {
  std::string ext = p.extension().string();
  if (ext.size() < 2) return false;
  return image_extensions().count(OIIO::Strutil::lower(ext.substr(1))) > 0;
}

// True when `inner` is `outer` or inside it (both canonical as far as they exist).
bool inside(const fs::path& inner, const fs::path& outer) {
  std::error_code ec;
  const fs::path a = fs::weakly_canonical(fs::absolute(inner), ec);
  const fs::path b = fs::weakly_canonical(fs::absolute(outer), ec);
  auto ai = a.begin();
  for (auto bi = b.begin(); bi != b.end(); ++bi, ++ai)
    if (ai == a.end() || *ai != *bi) return false;
  return true;
}

struct Found {
  std::string input;
  fs::path relative_dir;  // mirrored under the destination
  std::map<std::string, std::string> overrides;
  std::string failure;  // known before it runs (a pattern that matches nothing)
};

// A folder, walked recursively: its images, with their folders relative to it (hidden files and
// folders, such as temporaries, are left out).
void walk(const fs::path& dir, std::vector<Found>& out, std::size_t& not_images) {
  std::error_code ec;
  for (auto it =
           fs::recursive_directory_iterator(dir, fs::directory_options::skip_permission_denied, ec);
       !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
    const fs::path& p = it->path();
    if (p.filename().string().rfind('.', 0) == 0) {
      if (it->is_directory(ec)) it.disable_recursion_pending();
      continue;
    }
    if (!it->is_regular_file(ec)) continue;
    if (!is_image_name(p)) {
      ++not_images;
      continue;
    }
    out.push_back({p.string(), p.parent_path().lexically_relative(dir), {}, {}});
  }
}

// The lines of a list file: paths (relative to the list's folder), or JSON objects with "input"
// and any single-file setting for that file.
void read_list(const std::string& file, std::vector<Found>& out) {
  check_readable_file(file, "--inputs-from");
  std::ifstream f(file);
  const fs::path base = fs::path(file).parent_path();
  std::string line;
  for (int number = 1; std::getline(f, line); ++number) {
    const std::string where = quoted_path(file) + " line " + std::to_string(number) + ": ";
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    line = line.substr(first, line.find_last_not_of(" \t\r") - first + 1);
    Found item;
    std::string path = line;
    if (line[0] == '{') {
      Json j = Json::parse(line, nullptr, false);
      if (j.is_discarded() || !j.is_object() || !j.contains("input") || !j["input"].is_string())
        throw Error(where + "expected a path, or a JSON object with a string \"input\"");
      path = j["input"].get<std::string>();
      for (auto it = j.begin(); it != j.end(); ++it) {
        if (it.key() == "input") continue;
        const SettingSpec* spec = find_setting(it.key());
        if (!spec || !spec->recipe || !spec->applies(kIngest))
          throw Error(where + "unknown key " + quote(it.key()) +
                      " (a single-file setting: colorspace, mode, wavelengths, ...)");
        item.overrides[it.key()] = it->is_string() ? it->get<std::string>() : it->dump();
      }
    }
    const fs::path p(path);
    item.input = (p.is_relative() ? base / p : p).lexically_normal().string();
    item.relative_dir = p.is_relative() ? p.parent_path().lexically_normal() : fs::path();
    if (item.relative_dir.string().rfind("..", 0) == 0) item.relative_dir.clear();
    out.push_back(std::move(item));
  }
}

// The output's path relative to the destination, from the name pattern.
std::string output_name(const std::string& pattern, const Found& f) {
  const fs::path in(f.input);
  std::string out = pattern;
  auto replace = [&](const std::string& key, const std::string& value) {
    for (std::size_t at; (at = out.find(key)) != std::string::npos;)
      out.replace(at, key.size(), value);
  };
  replace("{dir}", f.relative_dir.string());
  replace("{stem}", in.stem().string());
  replace("{ext}", in.extension().string());
  std::string rel = fs::path(out).lexically_normal().string();
  while (rel.rfind("./", 0) == 0) rel = rel.substr(2);
  if (!rel.empty() && rel[0] == '/') rel = rel.substr(1);
  return rel;
}

// What identifies the OCIO config a batch uses, for the up-to-date key.
std::string config_identity(const Settings& s) {
  std::string path = s.config;
  if (path.empty())
    if (const char* env = std::getenv("OCIO"); env && *env) path = env;
  if (path.empty()) return "shipped";
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return path;
  return path + " " + std::to_string(st.st_size) + " " + std::to_string(st.st_mtim.tv_sec) + "." +
         std::to_string(st.st_mtim.tv_nsec);
}

// Everything an output depends on: the input's identity (path, size, time), the settings that
// shape the written file, the config and the version. Stored in the output's header.
std::string ingest_key(const IngestItem& item, const struct stat& st, const std::string& config) {
  std::error_code ec;
  std::string text = "spectralize " SPECTRALIZE_VERSION "|" +
                     fs::weakly_canonical(fs::absolute(item.input), ec).string() + "|" +
                     std::to_string(st.st_size) + "|" + std::to_string(st.st_mtim.tv_sec) + "." +
                     std::to_string(st.st_mtim.tv_nsec) + "|" + config;
  for (const auto& [key, value] : describe_settings(item.settings, kIngest)) {
    // Settings that do not change the written file: where it goes, how fast, what happens to
    // data files.
    if (key == "threads" || key == "jobs" || key == "cache" || key == "data" ||
        key == "name_pattern")
      continue;
    text += "|" + key + "=" + value;
  }
  return hex(fnv1a(text));
}

// A byte-for-byte copy through an AtomicOutput, with the input's modification time (so a rerun
// can tell it is up to date).
void copy_checked(const std::string& input, const std::string& output, const struct stat& st) {
  check_readable_file(input, "input");
  AtomicOutput out(output, std::span<const std::string>(&input, 1));
  std::ifstream in(input, std::ios::binary);
  std::vector<char> buf(1 << 20);
  while (in) {
    in.read(buf.data(), static_cast<std::streamsize>(buf.size()));
    if (in.gcount() > 0)
      out.write(std::string_view(buf.data(), static_cast<std::size_t>(in.gcount())));
  }
  if (in.bad()) throw Error(quoted_path(input) + ": cannot read it whole");
  out.commit();
  const struct timespec times[2] = {st.st_atim, st.st_mtim};
  ::utimensat(AT_FDCWD, output.c_str(), times, 0);
}

bool same_copy(const std::string& output, const struct stat& in) {
  struct stat st {};
  return ::stat(output.c_str(), &st) == 0 && S_ISREG(st.st_mode) && st.st_size == in.st_size &&
         st.st_mtim.tv_sec == in.st_mtim.tv_sec && st.st_mtim.tv_nsec == in.st_mtim.tv_nsec;
}

std::string manifest_part(int shard, int shards) {
  return "spectralize-ingest.part-" + std::to_string(shard) + "-of-" + std::to_string(shards) +
         ".jsonl";
}

Json summary_json(const IngestSummary& s) {
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
  j["seconds"] = s.seconds;
  return Json{{"summary", j}};
}

}  // namespace

std::string ingest_summary_json(const IngestSummary& summary) {
  Json j = summary_json(summary)["summary"];
  j["manifest"] = summary.manifest;
  return j.dump();
}

IngestPlan plan_ingest(const IngestRequest& request) {
  IngestPlan plan;
  plan.request = request;
  if (request.destination.empty()) throw Error("-o DESTDIR: the folder to write into is required");
  if (request.shards < 1 || request.shard < 0 || request.shard >= request.shards)
    throw Error("shard " + std::to_string(request.shard) + "/" + std::to_string(request.shards) +
                ": needs 0 <= I < N");
  std::vector<Found> found;
  for (const std::string& src : request.sources) {
    std::error_code ec;
    const fs::path p(src);
    if (fs::is_directory(p, ec)) {
      if (inside(request.destination, p))
        throw Error("-o " + quoted_path(request.destination) + " is inside the source folder " +
                    quoted_path(src) + ": its outputs would be ingested again; choose another");
      walk(p, found, plan.not_images);
    } else if (fs::exists(fs::symlink_status(p, ec))) {
      found.push_back({src, fs::path(), {}, {}});  // a file given by name: checked when run
    } else if (src.find_first_of("*?[") != std::string::npos) {
      // Matches mirror their folders below the pattern's fixed part ("lib/*/*.png" -> "walls/").
      fs::path fixed;
      for (const auto& part : p.parent_path()) {
        if (part.string().find_first_of("*?[") != std::string::npos) break;
        fixed /= part;
      }
      const std::size_t before = found.size();
      glob_t g{};
      if (::glob(src.c_str(), 0, nullptr, &g) == 0)
        for (std::size_t i = 0; i < g.gl_pathc; ++i)
          if (fs::is_regular_file(g.gl_pathv[i], ec) && is_image_name(g.gl_pathv[i]))
            found.push_back({g.gl_pathv[i],
                             fixed.empty()
                                 ? fs::path(g.gl_pathv[i]).parent_path()
                                 : fs::path(g.gl_pathv[i]).parent_path().lexically_relative(fixed),
                             {},
                             {}});
      globfree(&g);
      if (found.size() == before)
        found.push_back(
            {src, fs::path(), {}, quoted_path(src) + ": the pattern matches no image file"});
    } else {
      // A missing file is that file's failure (recorded when run); the others carry on.
      found.push_back({src, fs::path(), {}, {}});
    }
  }
  if (!request.inputs_from.empty()) read_list(request.inputs_from, found);
  if (found.empty()) throw Error("no input files found");

  // Name the outputs; two inputs for one output is a failure of both, never a silent overwrite.
  std::map<std::string, std::vector<IngestItem>> by_output;
  for (const Found& f : found) {
    IngestItem item;
    item.input = f.input;
    item.failure = f.failure;
    item.settings = request.settings;
    for (const auto& [key, value] : f.overrides)
      apply_setting(item.settings, *find_setting(key), value, "key '" + key + "' of " + f.input);
    item.relative = output_name(item.settings.ingest.name_pattern, f);
    if (item.failure.empty() && (item.relative.empty() || item.relative.rfind("..", 0) == 0))
      item.failure = "its output name '" + item.relative + "' leaves the destination";
    item.output = (fs::path(request.destination) / item.relative).string();
    by_output[item.relative].push_back(std::move(item));
  }
  // Same-stem siblings (a.png, a.tif, a.tx): one asset when derived, else each its own name;
  // two inputs still naming one output (two sources mirrored into one tree) fail, never a
  // silent overwrite.
  std::map<std::string, std::vector<IngestItem>> renamed;
  for (auto& [rel, items] : by_output) {
    if (items.size() > 1) {
      std::vector<std::string> inputs;
      for (const auto& i : items) inputs.push_back(i.input);
      const std::vector<SameStemDecision> d = decide_same_stem(inputs, rel);
      for (std::size_t k = 0; k < items.size(); ++k) {
        items[k].relative = d[k].relative;
        items[k].output = (fs::path(request.destination) / d[k].relative).string();
        items[k].derived_from = d[k].derived_from;
        items[k].note = d[k].note;
      }
    }
    for (auto& i : items) renamed[i.relative].push_back(std::move(i));
  }
  std::vector<IngestItem> all;
  for (auto& [rel, items] : renamed) {
    std::size_t writers = 0;
    for (const auto& i : items) writers += i.derived_from.empty();
    if (writers > 1) {
      std::string names;
      for (const auto& i : items) names += (names.empty() ? "" : ", ") + quoted_path(i.input);
      for (auto& i : items)
        if (i.failure.empty())
          i.failure = "inputs " + names + " would all be written to " + quoted_path(i.output) +
                      "; give them distinct names (--name-pattern)";
    }
    for (auto& i : items) all.push_back(std::move(i));
  }
  plan.all_items = all.size();
  // Shards by a hash of the output's name: the same split for every task, stable as files come
  // and go.
  for (auto& item : all)
    if (static_cast<int>(fnv1a(item.relative) % static_cast<std::uint64_t>(request.shards)) ==
        request.shard)
      plan.items.push_back(std::move(item));
  plan.manifest =
      !request.manifest.empty() ? request.manifest
      : request.shards > 1
          ? (fs::path(request.destination) / manifest_part(request.shard, request.shards)).string()
          : (fs::path(request.destination) / kManifestName).string();
  return plan;
}

namespace {

// What every file of a batch shares.
struct Batch {
  const IngestPlan& plan;
  const LogFn& log;
  std::string config;
  ThreadShare share;  // the batch's cores, split between the files converting now
  TablePool pool;
  std::atomic<std::uint64_t> stale{0};
  std::mutex swept_mutex;
  std::set<std::string> swept;  // output folders already cleared of stale temporaries

  /// Removes, once per folder, the temporaries killed earlier runs left there (any file's:
  /// outputs, copies, manifests; a live writer's are locked and stay). Cost: one listing.
  void sweep(const std::string& folder) {
    std::lock_guard<std::mutex> lock(swept_mutex);
    if (swept.insert(folder).second) stale += remove_stale_temporaries(folder);
  }
};

// One file: up to date, non-colour data (skipped or copied), converted, or failed; the record.
Json process(const IngestItem& item, Batch& batch) {
  const auto start = Clock::now();
  Json r;
  r["input"] = item.input;
  r["output"] = item.output;
  auto finish = [&](const std::string& status, const std::string& message = "") {
    r["status"] = status;
    if (!message.empty()) r["message"] = message;
    r["seconds"] = std::chrono::duration<double>(Clock::now() - start).count();
    return r;
  };
  try {
    if (!item.failure.empty()) throw Error(item.failure);
    if (!item.derived_from.empty()) {  // its source is converted (same_stem.h)
      r["source"] = item.derived_from;
      r["reason"] = item.note;
      return finish("derived");
    }
    if (!item.note.empty()) r["note"] = item.note;
    check_readable_file(item.input, "input");
    struct stat st {};
    ::stat(item.input.c_str(), &st);
    Settings s = item.settings;
    const std::string key = ingest_key(item, st, batch.config);
    const fs::path out(item.output);
    std::error_code ec;
    fs::create_directories(out.parent_path(), ec);
    if (!fs::is_directory(out.parent_path(), ec))
      throw Error(quoted_path(item.output) + ": cannot create the folder " +
                  quoted_path(out.parent_path().string()));
    batch.sweep(out.parent_path().string());
    // Non-colour data by the words of its name and folders (map_kind.h): never spectralized.
    const NameVerdict name =
        map_kind_by_name(item.input, name_words_in_force(s.data_names, s.colour_names));
    std::string data_reason = name.kind == MapKind::data ? "data by its " + name.reason : "";
    if (!data_reason.empty() && !name.warnings.empty()) r["warnings"] = name.warnings;
    // Up to date: the key recorded in the output's header, which also says how the file was
    // decided.
    if (!batch.plan.request.force && data_reason.empty()) {
      auto recorded = exr_string_attributes(item.output);
      if (recorded[kKeyAttribute] == key) {
        r["colorspace"] = recorded["spectralize:colorspace"];
        r["colorspace_reason"] = recorded["spectralize:colorspaceReason"];
        r["mode"] = recorded["spectralize:mode"];
        r["mode_reason"] = recorded["spectralize:modeReason"];
        return finish("up_to_date");
      }
    }
    if (data_reason.empty()) {
      // Data by an ambiguous word settled by the channels, or by a data colour space.
      ImageReader reader(item.input, static_cast<int>(s.spectral.grid.size()) + 4, true);
      const InputInterpretation in =
          interpret_colour(item.input, reader.spec(), s, ColourSpaces::load(s.config));
      data_reason = in.data_reason;
      if (!data_reason.empty() && !in.warnings.empty()) r["warnings"] = in.warnings;
    }
    if (!data_reason.empty()) {
      r["reason"] = data_reason;
      if (!s.ingest.copy_data) {
        r.erase("output");  // nothing is written
        return finish("skipped_data");
      }
      const std::string copy = (out.parent_path() / fs::path(item.input).filename()).string();
      r["output"] = copy;
      if (!batch.plan.request.force && same_copy(copy, st)) return finish("up_to_date");
      copy_checked(item.input, copy, st);
      return finish("copied_data");
    }
    const std::map<std::string, std::string> recorded = {{kKeyAttribute, key},
                                                         {"spectralize:source", item.input}};
    const ThreadShare::Running running(batch.share);
    r["threads"] = batch.share.now();  // at its start; files finishing give theirs later
    const ImageReport rep = run_image_job(item.input, item.output, s, nullptr, batch.log,
                                          &batch.pool, recorded, {}, &batch.share);
    r["colorspace"] = rep.colorspace;
    r["colorspace_reason"] = rep.colorspace_reason;
    r["mode"] = std::string(to_string(rep.settings.spectral.mode));
    r["mode_reason"] = rep.mode_reason;
    r["pixels"] = rep.pixels;
    r["out_of_gamut_pixels"] = rep.out_of_gamut_pixels();
    r["invalid_pixels"] = rep.counts.invalid;
    r["max_relative_xyz_error"] = rep.counts.max_error;
    if (!rep.warnings.empty()) r["warnings"] = rep.warnings;
    return finish("converted");
  } catch (const std::exception& e) {
    return finish("failed", e.what());
  }
}

}  // namespace

IngestSummary run_ingest(const IngestPlan& plan, const IngestProgressFn& progress,
                         const LogFn& log) {
  install_cleanup_handlers();
  const ReadFileScope reads;  // no output of the batch replaces a file it reads
  const auto t0 = Clock::now();
  const Settings& base = plan.request.settings;
  const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const int total_threads = base.threads > 0 ? base.threads : cores;
  const int files = static_cast<int>(std::max<std::size_t>(1, plan.items.size()));
  const int jobs = std::max(1, std::min(base.ingest.jobs > 0 ? base.ingest.jobs : cores, files));
  OIIO::attribute("threads", total_threads);
  OIIO::attribute("exr_threads", total_threads);
  std::error_code ec;
  fs::create_directories(plan.request.destination, ec);
  // The manifest's place is checked (and its temporary file made) before any work; a killed
  // earlier run's temporary manifest goes.
  Batch batch{plan, log, config_identity(base), ThreadShare(total_threads), {}, {}, {}, {}};
  // The manifest's folder too (a killed run's temporary manifest), unless it is a stream.
  const fs::path manifest_path(plan.manifest);
  if (!fs::exists(manifest_path, ec) || fs::is_regular_file(manifest_path, ec))
    batch.sweep(manifest_path.has_parent_path() ? manifest_path.parent_path().string() : ".");
  AtomicOutput manifest(plan.manifest, {}, /*allow_stream=*/true);

  std::vector<Json> records(plan.items.size());
  IngestSummary sum;
  std::mutex mutex;
  std::atomic<std::size_t> next{0};
  std::size_t done = 0;
  auto worker = [&] {
    for (std::size_t i; (i = next.fetch_add(1)) < plan.items.size();) {
      Json r = process(plan.items[i], batch);
      std::lock_guard<std::mutex> lock(mutex);
      const std::string status = r["status"];
      if (status == "converted") ++sum.converted, sum.pixels += r["pixels"].get<std::uint64_t>();
      if (status == "up_to_date") ++sum.up_to_date;
      if (status == "skipped_data") ++sum.skipped_data;
      if (status == "copied_data") ++sum.copied_data;
      if (status == "derived") ++sum.derived;
      if (status == "failed") ++sum.failed;
      if (progress)
        progress(++done, plan.items.size(),
                 status == "failed" ? "failed: " + r["message"].get<std::string>()
                                    : status + " " + plan.items[i].input);
      records[i] = std::move(r);
    }
  };
  std::vector<std::thread> threads;
  for (int j = 1; j < jobs; ++j) threads.emplace_back(worker);
  worker();
  for (auto& t : threads) t.join();
  for (const std::string& w : batch.pool.save()) log(0, w);

  sum.stale_temporaries_removed = batch.stale;
  sum.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  sum.manifest = plan.manifest;
  std::string text;
  for (const Json& r : records) text += r.dump() + "\n";
  text += summary_json(sum).dump() + "\n";
  manifest.write(text);
  manifest.commit();
  return sum;
}

IngestSummary merge_ingest_manifests(const std::string& destination) {
  const std::regex part(R"(spectralize-ingest\.part-(\d+)-of-(\d+)\.jsonl)");
  std::map<int, fs::path> parts;
  int shards = 0;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(destination, ec)) {
    std::smatch m;
    const std::string name = e.path().filename().string();
    if (!std::regex_match(name, m, part)) continue;
    const int n = std::stoi(m[2]);
    if (shards && n != shards)
      throw Error(quoted_path(destination) + ": manifest parts of " + std::to_string(shards) +
                  " and of " + std::to_string(n) + " shards; remove the stale ones");
    shards = n;
    parts[std::stoi(m[1])] = e.path();
  }
  if (ec) throw Error(quoted_path(destination) + ": " + ec.message());
  if (!shards) throw Error(quoted_path(destination) + ": no manifest parts to merge");
  std::string missing;
  for (int i = 0; i < shards; ++i)
    if (!parts.count(i)) missing += (missing.empty() ? "" : ", ") + std::to_string(i);
  if (!missing.empty())
    throw Error(quoted_path(destination) + ": the manifests of shards " + missing + " of " +
                std::to_string(shards) + " are missing (did those tasks finish?)");
  IngestSummary sum;
  std::string text;
  for (const auto& [i, path] : parts) {
    std::ifstream f(path);
    std::string line;
    for (int number = 1; std::getline(f, line); ++number) {
      Json r = Json::parse(line, nullptr, false);
      if (r.is_discarded() || !r.is_object())
        throw Error(quoted_path(path.string()) + " line " + std::to_string(number) + ": not JSON");
      if (r.contains("summary")) {
        sum.seconds = std::max(sum.seconds, r["summary"].value("seconds", 0.0));
        sum.stale_temporaries_removed += r["summary"].value("stale_temporaries_removed", 0);
        continue;
      }
      const std::string status = r.value("status", "");
      if (status == "converted") ++sum.converted, sum.pixels += r.value("pixels", std::uint64_t{0});
      if (status == "up_to_date") ++sum.up_to_date;
      if (status == "skipped_data") ++sum.skipped_data;
      if (status == "copied_data") ++sum.copied_data;
      if (status == "derived") ++sum.derived;
      if (status == "failed") ++sum.failed;
      text += r.dump() + "\n";
    }
  }
  text += summary_json(sum).dump() + "\n";
  sum.manifest = (fs::path(destination) / kManifestName).string();
  AtomicOutput out(sum.manifest, {});
  out.write(text);
  out.commit();
  return sum;
}

}  // namespace spectralize
