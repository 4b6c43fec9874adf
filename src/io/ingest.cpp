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
#include "io/safe_output.h"
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
    out.push_back({p.string(), p.parent_path().lexically_relative(dir), {}});
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

// A word of a file name found in a rule list, and where it ends in the name (the index of its
// last part: name_words lists the parts, then each pair of neighbours).
struct WordHit {
  std::string word;
  int end = -1;
  explicit operator bool() const { return !word.empty(); }
};

// The longest word of the name that is in `list` ("basecolor" rather than "color").
WordHit word_in(const std::vector<std::string>& words, const std::string& list) {
  std::set<std::string> names;
  for (const auto& n : OIIO::Strutil::splits(list, ",")) names.insert(n);
  const int parts = static_cast<int>(words.size() + 1) / 2;
  WordHit hit;
  for (int i = 0; i < static_cast<int>(words.size()); ++i)
    if (names.count(words[i]) && words[i].size() > hit.word.size())
      hit = {words[i], i < parts ? i : i - parts + 1};
  return hit;
}

// Whether `a` names the map rather than `b`: texture names put the map's kind last
// ("metal_plate_basecolor" is a colour map of a metal plate), then the longer word.
bool names_the_map(const WordHit& a, const WordHit& b) {
  if (!b) return true;
  return a.end != b.end ? a.end > b.end : a.word.size() > b.word.size();
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
  j["failed"] = s.failed;
  j["pixels"] = s.pixels;
  j["stale_temporaries_removed"] = s.stale_temporaries_removed;
  j["seconds"] = s.seconds;
  if (s.interrupted) {
    j["interrupted"] = true;
    j["not_done"] = s.not_done;
  }
  return Json{{"summary", j}};
}

}  // namespace

std::string ingest_summary_json(const IngestSummary& summary) {
  Json j = summary_json(summary)["summary"];
  j["manifest"] = summary.manifest;
  return j.dump();
}

std::vector<std::string> name_words(const std::string& stem) {
  std::vector<std::string> parts;
  std::string cur;
  for (std::size_t i = 0; i < stem.size(); ++i) {
    const unsigned char c = static_cast<unsigned char>(stem[i]);
    if (!std::isalnum(c)) {
      if (!cur.empty()) parts.push_back(cur);
      cur.clear();
      continue;
    }
    // "BaseColor" -> "Base", "Color": a capital after a lower-case letter starts a word.
    if (std::isupper(c) && i > 0 && std::islower(static_cast<unsigned char>(stem[i - 1])) &&
        !cur.empty()) {
      parts.push_back(cur);
      cur.clear();
    }
    cur += static_cast<char>(std::tolower(c));
  }
  if (!cur.empty()) parts.push_back(cur);
  std::vector<std::string> words = parts;
  for (std::size_t i = 0; i + 1 < parts.size(); ++i) words.push_back(parts[i] + parts[i + 1]);
  return words;
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
      found.push_back({src, fs::path(), {}});  // a file given by name: checked when run
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
      found.push_back({src, fs::path(), {}});
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
  std::vector<IngestItem> all;
  for (auto& [rel, items] : by_output) {
    if (items.size() > 1) {
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

// Thrown through a conversion when the batch is asked to stop.
struct Interrupted : std::exception {
  const char* what() const noexcept override { return "interrupted"; }
};

// What every file of a batch shares.
struct Batch {
  const IngestPlan& plan;
  const LogFn& log;
  std::string config;
  int threads_per_job = 1;
  TablePool pool;
  std::atomic<std::uint64_t> stale{0};
  std::mutex swept_mutex{};
  std::set<std::string> swept{};            // output folders already cleared of stale temporaries
  const std::atomic<bool>* stop = nullptr;  // asked to stop (may be null)
  bool stopping() const { return stop && stop->load(); }

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
    check_readable_file(item.input, "input");
    struct stat st {};
    ::stat(item.input.c_str(), &st);
    Settings s = item.settings;
    s.threads = batch.threads_per_job;
    const std::string key = ingest_key(item, st, batch.config);
    const fs::path out(item.output);
    std::error_code ec;
    fs::create_directories(out.parent_path(), ec);
    if (!fs::is_directory(out.parent_path(), ec))
      throw Error(quoted_path(item.output) + ": cannot create the folder " +
                  quoted_path(out.parent_path().string()));
    batch.sweep(out.parent_path().string());
    // Non-colour data by its name: never spectralized.
    const std::vector<std::string> words = name_words(fs::path(item.input).stem().string());
    const WordHit data = word_in(words, s.ingest.data_names);
    const WordHit light = word_in(words, s.ingest.emission_names);
    const WordHit surface = word_in(words, s.ingest.reflectance_names);
    const WordHit& colour = names_the_map(light, surface) ? light : surface;
    std::string data_reason;
    if (data && names_the_map(data, colour)) data_reason = "data name rule '" + data.word + "'";
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
    InputInterpretation in;
    if (data_reason.empty()) {
      // Non-colour data by its colour space (a file rule, or the file's metadata).
      ImageReader reader(item.input, static_cast<int>(s.spectral.grid.size()) + 4, true);
      const ColourSpaces spaces = ColourSpaces::load(s.config);
      in = interpret_input(item.input, reader.spec(), s, spaces);
      if (spaces.is_data(in.colorspace))
        data_reason = "colour space '" + in.colorspace + "' is data (" + in.colorspace_reason + ")";
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
    // Mode by name rules, before the data type decides.
    std::string mode_reason;
    if (s.mode == ModeChoice::automatic) {
      if (light || surface) {
        s.mode = &colour == &light ? ModeChoice::emission : ModeChoice::reflectance;
        mode_reason = "name rule '" + colour.word + "'";
      }
    }
    std::map<std::string, std::string> recorded = {{kKeyAttribute, key},
                                                   {"spectralize:source", item.input}};
    if (!mode_reason.empty()) recorded["spectralize:modeReason"] = mode_reason;
    // Between strips: a stop request abandons the conversion (its temporary is removed).
    const ProgressFn check_stop = [&batch](std::uint64_t, std::uint64_t) {
      if (batch.stopping()) throw Interrupted();
    };
    const ImageReport rep =
        run_image_job(item.input, item.output, s, check_stop, batch.log, &batch.pool, recorded);
    r["colorspace"] = rep.colorspace;
    r["colorspace_reason"] = rep.colorspace_reason;
    r["mode"] = std::string(to_string(rep.settings.spectral.mode));
    r["mode_reason"] = mode_reason.empty() ? rep.mode_reason : mode_reason;
    r["pixels"] = rep.pixels;
    r["out_of_gamut_pixels"] = rep.out_of_gamut_pixels();
    r["invalid_pixels"] = rep.counts.invalid;
    r["max_relative_xyz_error"] = rep.counts.max_error;
    if (!rep.warnings.empty()) r["warnings"] = rep.warnings;
    return finish("converted");
  } catch (const Interrupted&) {
    return Json();  // not done: no record, so a rerun does it
  } catch (const std::exception& e) {
    return finish("failed", e.what());
  }
}

}  // namespace

IngestSummary run_ingest(const IngestPlan& plan, const IngestProgressFn& progress, const LogFn& log,
                         const std::atomic<bool>* stop) {
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
  Batch batch{plan, log, config_identity(base), std::max(1, total_threads / jobs), {}, {}};
  batch.stop = stop;
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
    ensure_signal_stack();  // a crash on this thread still removes the batch's temporaries
    for (std::size_t i; (i = next.fetch_add(1)) < plan.items.size();) {
      if (batch.stopping()) break;
      Json r = process(plan.items[i], batch);
      std::lock_guard<std::mutex> lock(mutex);
      if (r.is_null()) continue;  // interrupted
      const std::string status = r["status"];
      if (status == "converted") ++sum.converted, sum.pixels += r["pixels"].get<std::uint64_t>();
      if (status == "up_to_date") ++sum.up_to_date;
      if (status == "skipped_data") ++sum.skipped_data;
      if (status == "copied_data") ++sum.copied_data;
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
  sum.interrupted = batch.stopping();
  std::string text;
  for (const Json& r : records) {
    if (r.is_null()) {
      ++sum.not_done;  // not started, or abandoned by the interruption
      continue;
    }
    text += r.dump() + "\n";
    // Kept for callers that cannot read the manifest back (a stream, /dev/stdout).
    if (r.value("status", "") == "failed") sum.failures.push_back(r.dump());
  }
  sum.interrupted = sum.interrupted && sum.not_done > 0;
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
