// Planning a batch (docs/DESIGN.md §12): the walk of the sources with everything it leaves out
// named, each input once whatever its spellings, the outputs named and planned against every
// file the batch reads and against each other, this shard's files and the batch's identity.

#include <OpenImageIO/imageio.h>
#include <fnmatch.h>
#include <glob.h>
#include <sys/stat.h>

#include <algorithm>
#include <cinttypes>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <set>

#include "colour/colour_space.h"
#include "imagefile/safe_output.h"
#include "ingest/ingest.h"
#include "ingest/same_stem.h"
#include "ingest/shard.h"
#include "spectralize/core/error.h"
#include "spectralize/version.h"
#include "text/strings.h"

namespace fs = std::filesystem;

namespace spectralize {

namespace {

using Json = nlohmann::ordered_json;

constexpr const char* kManifestName = "spectralize-ingest.jsonl";

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

using Identity = std::pair<std::uint64_t, std::uint64_t>;  // device, inode

std::optional<Identity> identity(const fs::path& p) {
  struct stat st = {};
  if (::stat(p.c_str(), &st) != 0) return std::nullopt;
  return Identity{static_cast<std::uint64_t>(st.st_dev), static_cast<std::uint64_t>(st.st_ino)};
}

// True when `inner` is the folder `outer` or inside it, by identity: links, "..", bind mounts.
bool inside(const fs::path& inner, const fs::path& outer) {
  const auto o = identity(outer);
  if (!o) return false;
  std::error_code ec;
  for (fs::path p = fs::weakly_canonical(fs::absolute(inner, ec), ec);; p = p.parent_path()) {
    if (identity(p) == o) return true;
    if (!p.has_relative_path()) return false;
  }
}

std::string file_kind(const struct stat& st) {
  return S_ISFIFO(st.st_mode)   ? "a pipe"
         : S_ISCHR(st.st_mode)  ? "a character device"
         : S_ISBLK(st.st_mode)  ? "a block device"
         : S_ISSOCK(st.st_mode) ? "a socket"
                                : "not a file";
}

struct Found {
  std::string input;
  fs::path relative_dir;  // mirrored under the destination
  std::map<std::string, std::string> overrides;
  std::string failure;  // known before it runs (a pattern that matches nothing)
  std::string origin;   // a list line's "origin" object, as JSON text ("" : none)
  bool listed = false;  // from a list line: its settings are the file's, over a walk's finding
  fs::path mirror;      // a list line's "as": the path the output mirrors ("" : the input's)
};

// Why a path met by the walk or a pattern is not an input, or "" when it is one (a regular
// image file, followed through links). `folder` is set for a folder to walk.
std::string not_an_input(const fs::path& p, bool& folder, bool& failure, std::string& kind) {
  folder = failure = false;
  struct stat lst = {}, st = {};
  if (::lstat(p.c_str(), &lst) != 0) {
    failure = true;
    kind = "unexaminable";
    return std::string("cannot be examined: ") + std::strerror(errno);
  }
  const bool link = S_ISLNK(lst.st_mode);
  if (::stat(p.c_str(), &st) != 0) {
    const int err = errno;
    kind = link && err == ENOENT ? "dangling_link" : "unexaminable";
    if (link && err == ENOENT) return "a dangling symbolic link";
    failure = true;
    return (link ? "a symbolic link that cannot be followed: " : "cannot be examined: ") +
           std::string(std::strerror(err));
  }
  if (S_ISDIR(st.st_mode)) {
    folder = true;
    return "";
  }
  kind = "not_regular";
  if (!S_ISREG(st.st_mode))
    return "not a regular file (" + file_kind(st) + (link ? ", by a symbolic link)" : ")");
  kind = "not_image";
  if (!is_image_name(p)) return "not an image (by its extension)";
  kind.clear();
  return "";
}

// The recursive walk of a source folder: its images with their folders relative to it, and
// everything else named in `left`. Links to folders are followed once; a loop and a folder that
// cannot be read are failures.
class Walker {
 public:
  Walker(std::vector<Found>& found, std::vector<LeftOut>& left, std::optional<Identity> dest)
      : found_(found), left_(left), destination_(dest) {}

  void walk(const fs::path& root) {
    const auto id = identity(root);
    if (!id) return;
    if (visited_.count(*id)) {
      left_.push_back({root.string(), "same_folder",
                       "the same folder as " + quoted_path(visited_[*id]), false});
      return;
    }
    visited_[*id] = root.string();
    visit(root, fs::path(), {*id});
  }

 private:
  void visit(const fs::path& dir, const fs::path& rel, std::set<Identity> ancestors) {
    std::error_code ec;
    fs::directory_iterator it(dir, ec);
    if (ec) {
      left_.push_back({dir.string(), "unreadable_folder",
                       "a folder that cannot be read: " + ec.message(), true});
      return;
    }
    std::vector<fs::path> entries;
    for (; it != fs::directory_iterator(); it.increment(ec)) entries.push_back(it->path());
    if (ec)
      left_.push_back({dir.string(), "unreadable_folder",
                       "a folder that cannot be read to the end: " + ec.message(), true});
    // The same order on every machine (shards agree, manifests compare).
    std::sort(entries.begin(), entries.end());
    for (const fs::path& p : entries) {
      const std::string name = p.filename().string();
      if (name.rfind('.', 0) == 0) {
        struct stat st = {};
        const bool dir_entry = ::lstat(p.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
        const bool temporary = is_temporary_name(name);
        left_.push_back({p.string(), temporary ? "temporary" : "hidden",
                         temporary   ? "a temporary file of spectralize (a killed run's)"
                         : dir_entry ? "a hidden folder (not walked)"
                                     : "a hidden file",
                         false});
        continue;
      }
      bool folder = false, failure = false;
      std::string kind;
      const std::string why = not_an_input(p, folder, failure, kind);
      if (!why.empty()) {
        left_.push_back({p.string(), kind, why, failure});
        continue;
      }
      if (!folder) {
        found_.push_back({p.string(), rel, {}, {}, {}, false, {}});
        continue;
      }
      const auto id = identity(p);
      if (!id) continue;
      if (destination_ && *id == *destination_) {
        left_.push_back({p.string(), "destination",
                         "the destination folder (its outputs are never inputs)", false});
      } else if (ancestors.count(*id)) {
        left_.push_back(
            {p.string(), "loop", "a loop: a link back to " + quoted_path(visited_[*id]), true});
      } else if (visited_.count(*id)) {
        left_.push_back({p.string(), "same_folder",
                         "the same folder as " + quoted_path(visited_[*id]) + " (walked once)",
                         false});
      } else {
        visited_[*id] = p.string();
        std::set<Identity> deeper = ancestors;
        deeper.insert(*id);
        visit(p, rel / name, std::move(deeper));
      }
    }
  }

  std::vector<Found>& found_;
  std::vector<LeftOut>& left_;
  std::optional<Identity> destination_;
  std::map<Identity, std::string> visited_;
};

// The folders glob() could not read, from its error callback (a C function without a user
// pointer: one expansion at a time).
std::mutex g_glob_mutex;
std::vector<std::pair<std::string, int>>* g_glob_errors = nullptr;
extern "C" int glob_error(const char* path, int err) {
  if (g_glob_errors) g_glob_errors->emplace_back(path, err);
  return 0;  // go on with the rest
}

// The folder a pattern starts in (its components before the first wildcard) and the
// components from there ("lib/*/*.png" -> "lib", {"*", "*.png"}).
std::pair<fs::path, std::vector<std::string>> split_pattern(const std::string& pattern) {
  fs::path fixed;
  std::vector<std::string> rest;
  for (const auto& part : fs::path(pattern)) {
    const std::string t = part.string();
    if (rest.empty() && t.find_first_of("*?[") == std::string::npos)
      fixed /= part;
    else
      rest.push_back(t);
  }
  return {fixed, rest};
}

// True when the pattern could match a file inside `destination` (its outputs, on a rerun).
bool pattern_reaches(const std::string& pattern, const std::string& destination) {
  auto [fixed, rest] = split_pattern(pattern);
  std::error_code ec;
  const fs::path base = fs::weakly_canonical(fs::absolute(fixed.empty() ? "." : fixed), ec);
  const fs::path dest = fs::weakly_canonical(fs::absolute(destination), ec);
  const fs::path rel = dest.lexically_relative(base);
  if (rel.empty() || *rel.begin() == "..") return inside(destination, base) && !rest.empty();
  std::vector<std::string> parts;
  for (const auto& p : rel)
    if (p != ".") parts.push_back(p.string());
  if (rest.size() <= parts.size()) return false;
  for (std::size_t i = 0; i < parts.size(); ++i)
    if (::fnmatch(rest[i].c_str(), parts[i].c_str(), FNM_PERIOD) != 0) return false;
  return true;
}

// The matches of a glob pattern, mirroring their folders below its fixed part.
void expand(const std::string& pattern, std::vector<Found>& found, std::vector<LeftOut>& left) {
  const fs::path fixed = split_pattern(pattern).first;
  const std::size_t before = found.size();
  std::vector<std::pair<std::string, int>> errors;
  glob_t g{};
  {
    std::lock_guard<std::mutex> lock(g_glob_mutex);
    g_glob_errors = &errors;
    const int rc = ::glob(pattern.c_str(), 0, glob_error, &g);
    g_glob_errors = nullptr;
    if (rc != 0 && rc != GLOB_NOMATCH)
      left.push_back({pattern, "unexpandable_pattern", "the pattern could not be expanded", true});
  }
  for (const auto& [path, err] : errors)
    left.push_back({path, "unreadable_folder",
                    std::string("a folder that cannot be read: ") + std::strerror(err), true});
  for (std::size_t i = 0; i < g.gl_pathc; ++i) {
    const fs::path p(g.gl_pathv[i]);
    bool folder = false, failure = false;
    std::string kind;
    std::string why = not_an_input(p, folder, failure, kind);
    if (folder) {
      kind = "folder_match";
      why = "a folder (a pattern matches files: give the folder itself to walk it)";
    }
    if (!why.empty()) {
      left.push_back({p.string(), kind, why, failure});
      continue;
    }
    found.push_back({p.string(),
                     fixed.empty() ? p.parent_path() : p.parent_path().lexically_relative(fixed),
                     {},
                     {},
                     {},
                     false,
                     {}});
  }
  globfree(&g);
  if (found.size() == before)
    found.push_back({pattern,
                     fs::path(),
                     {},
                     quoted_path(pattern) + ": the pattern matches no image file",
                     {},
                     false,
                     {}});
}

// A list line's "origin": an object, recorded in the file's manifest record; its
// "colorspace_reason" and "mode_reason", where given, must be strings (they become reasons).
std::string origin_of(const Json& j, const std::string& where) {
  const Json& o = j["origin"];
  if (!o.is_object()) throw Error(where + "\"origin\" must be a JSON object");
  for (const char* key : {"colorspace_reason", "mode_reason", "where"})
    if (o.contains(key) && !o[key].is_string())
      throw Error(where + "\"origin\": \"" + key + "\" must be a string");
  return o.dump();
}

// The lines of a list file: paths (relative to the list's folder), or JSON objects with "input"
// (relative to "source", a folder, where given: the output mirrors the input's place in it),
// "origin" (where the line comes from, recorded) and any single-file setting for that file.
void read_list(const std::string& file, std::vector<Found>& out) {
  check_readable_file(file, "--inputs-from");
  std::ifstream f(file);
  const fs::path list_folder = fs::path(file).parent_path();
  std::string line;
  for (int number = 1; std::getline(f, line); ++number) {
    const std::string where = quoted_path(file) + " line " + std::to_string(number) + ": ";
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    line = line.substr(first, line.find_last_not_of(" \t\r") - first + 1);
    Found item;
    std::string path = line;
    fs::path base = list_folder;
    if (line[0] == '{') {
      Json j = Json::parse(line, nullptr, false);
      if (j.is_discarded() || !j.is_object() || !j.contains("input") || !j["input"].is_string())
        throw Error(where + "expected a path, or a JSON object with a string \"input\"");
      path = j["input"].get<std::string>();
      for (auto it = j.begin(); it != j.end(); ++it) {
        if (it.key() == "input") continue;
        if (it.key() == "source") {
          if (!it->is_string() || it->get<std::string>().empty())
            throw Error(where + "\"source\" must be a folder's path");
          const fs::path source(it->get<std::string>());
          base = source.is_relative() ? list_folder / source : source;
          continue;
        }
        if (it.key() == "origin") {
          item.origin = origin_of(j, where);
          continue;
        }
        if (it.key() == "as") {  // the relative path the output mirrors instead
          const fs::path as = it->is_string() ? fs::path(it->get<std::string>()) : fs::path();
          if (as.empty() || as.is_absolute() || !as.has_filename() ||
              as.lexically_normal().string().rfind("..", 0) == 0)
            throw Error(where + "\"as\" must be a relative file path inside the destination");
          item.mirror = as.lexically_normal();
          continue;
        }
        if (it.key() == "failure") {  // what is known to fail (a USD prim with no file)
          if (!it->is_string() || it->get<std::string>().empty())
            throw Error(where + "\"failure\" must be a reason");
          item.failure = it->get<std::string>();
          continue;
        }
        const SettingSpec* spec = find_setting(it.key());
        if (!spec || !spec->recipe || !spec->applies(kIngest))
          throw Error(where + "unknown key " + quote(it.key()) +
                      " (source, as, origin, failure, or a single-file setting: colorspace, mode, "
                      "wavelengths, ...)");
        item.overrides[it.key()] = it->is_string() ? it->get<std::string>() : it->dump();
      }
    }
    const fs::path p(path);
    item.input = (p.is_relative() ? base / p : p).lexically_normal().string();
    item.relative_dir = p.is_relative() ? p.parent_path().lexically_normal() : fs::path();
    if (item.relative_dir.string().rfind("..", 0) == 0) item.relative_dir.clear();
    if (!item.mirror.empty()) item.relative_dir = item.mirror.parent_path();
    item.listed = true;
    out.push_back(std::move(item));
  }
  if (f.bad()) throw FileError(quoted_path(file) + ": cannot be read to the end");
}

// The output's path relative to the destination, from the name pattern.
std::string output_name(const std::string& pattern, const Found& f) {
  const fs::path in(f.mirror.empty() ? fs::path(f.input) : f.mirror);
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

// The OCIO config the batch reads (given, else $OCIO), for the plan.
std::string config_path(const Settings& s) {
  if (!s.config.empty()) return s.config;
  const char* env = std::getenv("OCIO");
  return env && *env ? env : "";
}

// The settings that make a batch what it is (not how fast it runs), for its identity.
std::string batch_settings(const Settings& s) {
  std::string text;
  for (const auto& [key, value] : describe_settings(s, kIngest))
    if (key != "threads" && key != "jobs" && key != "cache" && key != "config")
      text += key + "=" + value + "\n";
  return text;
}

}  // namespace

IngestPlan plan_ingest(const IngestRequest& request) {
  return plan_ingest(request, std::nullopt);
}

IngestPlan plan_ingest(const IngestRequest& request, std::optional<JobPlan> job) {
  IngestPlan plan;
  plan.request = request;
  const std::string& dest = request.destination;
  if (dest.empty()) throw Error("-o DESTDIR: the folder to write into is required");
  if (request.shards < 1 || request.shard < 0 || request.shard >= request.shards)
    throw Error("shard " + std::to_string(request.shard) + "/" + std::to_string(request.shards) +
                ": needs 0 <= I < N");
  {
    std::error_code ec;
    if (fs::exists(dest, ec) && !fs::is_directory(dest, ec))
      throw FileError("-o " + quoted_path(dest) +
                      ": is not a folder (ingest writes a tree of files into a folder)");
  }
  const std::optional<Identity> dest_id = identity(dest);
  std::vector<Found> found;
  Walker walker(found, plan.left_out, dest_id);
  for (const std::string& src : request.sources) {
    std::error_code ec;
    const fs::path p(src);
    if (fs::is_directory(p, ec)) {
      if (inside(dest, p))
        throw Error("-o " + quoted_path(dest) + " is inside the source folder " + quoted_path(src) +
                    ": its outputs would be ingested again; choose another");
      walker.walk(p);
    } else if (fs::exists(fs::symlink_status(p, ec))) {
      found.push_back(
          {src, fs::path(), {}, {}, {}, false, {}});  // a file given by name: checked when run
    } else if (src.find_first_of("*?[") != std::string::npos) {
      if (pattern_reaches(src, dest))
        throw Error("-o " + quoted_path(dest) + " is where the pattern " + quoted_path(src) +
                    " looks for files: its outputs would be ingested again; choose another");
      expand(src, found, plan.left_out);
    } else {
      // A missing file is that file's failure (recorded when run); the others carry on.
      found.push_back({src, fs::path(), {}, {}, {}, false, {}});
    }
  }
  if (!request.inputs_from.empty()) read_list(request.inputs_from, found);
  for (const std::string& list : request.made_lists) read_list(list, found);
  if (found.empty() && plan.left_out.empty()) throw Error("no input files found");

  // Each file once, whatever its spellings ("lib lib", "lib ./lib/", a file given twice, a
  // link to it), unless a list gives it other settings; a file a list line gives is taken
  // with that line's settings, not as a walk or pattern found it.
  {
    std::map<Identity, std::string> listed;
    for (const Found& f : found)
      if (f.listed && f.failure.empty())
        if (const auto id = identity(f.input)) listed.emplace(*id, f.input);
    std::map<std::pair<Identity, std::string>, std::string> first;
    std::vector<Found> unique;
    for (Found& f : found) {
      const auto id = f.failure.empty() ? identity(f.input) : std::nullopt;
      if (id && !f.listed) {
        if (const auto it = listed.find(*id); it != listed.end()) {
          plan.left_out.push_back({f.input, "duplicate",
                                   "the same file as " + quoted_path(it->second) +
                                       ", which a list line gives (taken with its settings)",
                                   false});
          continue;
        }
      }
      if (id) {
        std::string settings;
        for (const auto& [k, v] : f.overrides) settings += k + "=" + v + "\n";
        auto [it, fresh] = first.emplace(std::pair{*id, settings}, f.input);
        if (!fresh) {
          plan.left_out.push_back({f.input, "duplicate",
                                   "the same file as " + quoted_path(it->second) + " (taken once)",
                                   false});
          continue;
        }
      }
      unique.push_back(std::move(f));
    }
    found = std::move(unique);
  }

  // What the batch reads: every input, the list, the config and the files it reads.
  FilePlan& files = plan.files;
  for (const Found& f : found) files.read(f.input, "the input");
  if (!request.inputs_from.empty()) files.read(request.inputs_from, "the --inputs-from list");
  for (const std::string& list : request.made_lists) files.read(list, "a list of inputs");
  {
    plan.job = job ? std::move(*job) : plan_to_spectral(request.settings, "", request.names);
    const ColourSpaces& spaces = plan.job.colour_spaces();
    plan.config_identity = spaces.content_identity();
    // A built-in config (ocio://...) is no file: its content enters the identity above.
    if (const std::string config = config_path(request.settings);
        !config.empty() && config.rfind("ocio://", 0) != 0)
      files.read(config, "the OCIO config");
    for (const auto& [src, resolved] : spaces.referenced_files())
      if (!resolved.empty()) files.read(resolved, "a file of the OCIO config");
  }

  // Name the outputs; a file known to fail writes nothing and names none.
  std::map<std::string, std::vector<IngestItem>> by_output;
  std::vector<IngestItem> known_failures;
  for (const Found& f : found) {
    IngestItem item;
    item.input = f.input;
    item.failure = f.failure;
    item.origin = f.origin;
    item.settings = request.settings;
    item.source_relative =
        (f.relative_dir / (f.mirror.empty() ? fs::path(f.input) : f.mirror).filename()).string();
    for (const auto& [key, value] : f.overrides)
      apply_setting(item.settings, *find_setting(key), value, "key '" + key + "' of " + f.input);
    item.settings.stated_for_file = f.overrides.count("colorspace") + f.overrides.count("mode") > 0;
    // The reasons of what the line gives, where its origin states them.
    if (!f.origin.empty()) {
      const Json origin = Json::parse(f.origin);
      auto reason = [&](const char* setting, const char* key, std::string& into) {
        if (f.overrides.count(setting) && origin.contains(key))
          into = origin[key].get<std::string>();
      };
      reason("colorspace", "colorspace_reason", item.settings.colorspace_given_by);
      reason("mode", "mode_reason", item.settings.mode_given_by);
    }
    item.relative = output_name(item.settings.ingest.name_pattern, f);
    if (item.failure.empty() && (item.relative.empty() || item.relative.rfind("..", 0) == 0))
      item.failure = "its output name '" + item.relative + "' leaves the destination";
    item.output = (fs::path(dest) / item.relative).string();
    if (item.settings.ingest.copy_data)
      item.copy = (fs::path(item.output).parent_path() / fs::path(f.input).filename()).string();
    if (!f.failure.empty()) {  // writes nothing: no output to name in its record
      item.copy.clear();
      item.output.clear();
      known_failures.push_back(std::move(item));
      continue;
    }
    by_output[item.relative].push_back(std::move(item));
  }
  // Same-stem siblings (a.png, a.tif, a.tx): one asset when derived, else each its own name
  // (same_stem.h); two inputs still naming one output (two sources mirrored into one tree)
  // are a failure of both, never a silent overwrite.
  std::map<std::string, std::vector<IngestItem>> renamed;
  for (auto& [rel, items] : by_output) {
    if (items.size() > 1) {
      std::vector<std::string> inputs;
      for (const auto& i : items) inputs.push_back(i.input);
      const std::vector<SameStemDecision> d = decide_same_stem(inputs, rel);
      for (std::size_t k = 0; k < items.size(); ++k) {
        IngestItem& i = items[k];
        i.relative = d[k].relative;
        i.output = (fs::path(dest) / d[k].relative).string();
        i.derived_from = d[k].derived_from;
        i.note = d[k].note;
        if (!i.derived_from.empty()) i.copy.clear();  // nothing of it is written
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
  for (auto& i : known_failures) all.push_back(std::move(i));
  // Every file the batch writes, against every file it reads and each other, in one order for
  // every shard: outputs first, then the copies of data files (an output wins over a copy),
  // then the manifest (which refuses the batch). A derived input writes nothing: its source's
  // output is its asset.
  for (IngestItem& i : all)
    if (i.failure.empty() && i.derived_from.empty()) {
      const std::string what = "the output of " + quoted_path(i.input);
      i.failure = files.write(i.output, what, WriteRules::named(what).below(dest));
    }
  for (IngestItem& i : all)
    if (i.failure.empty() && !i.copy.empty()) {
      const std::string what = "the copy of " + quoted_path(i.input);
      i.copy_failure = files.write(i.copy, what, WriteRules::named(what).below(dest));
    }
  plan.manifest = !request.manifest.empty() ? request.manifest
                  : request.shards > 1
                      ? (fs::path(dest) / part_name({request.shard, request.shards})).string()
                      : (fs::path(dest) / kManifestName).string();
  {
    const WriteRules rules =
        WriteRules::named(request.manifest.empty() ? "the manifest" : "the --manifest")
            .streams()
            .below(request.manifest.empty() ? dest : std::string());
    if (std::string why = files.write(plan.manifest, rules.what, rules); !why.empty())
      throw FileError((request.manifest.empty() ? "" : "--manifest ") + why);
  }

  // The batch's identity: its files, their names and settings, the config's content and N.
  std::uint64_t id =
      fnv1a("spectralize " SPECTRALIZE_VERSION " batch of " + std::to_string(request.shards) +
            "\n" + plan.config_identity + "\n" + batch_settings(request.settings));
  for (const IngestItem& i : all) id = fnv1a(i.relative + '\0' + i.source_relative + '\0', id);
  char buf[24];
  std::snprintf(buf, sizeof buf, "%016" PRIx64, id);
  plan.batch = buf;

  plan.all_items = all.size();
  // Shards by a hash of the output's name: the same split for every task, stable as files come
  // and go.
  for (auto& item : all)
    if (static_cast<int>(fnv1a(item.relative) % static_cast<std::uint64_t>(request.shards)) ==
        request.shard)
      plan.items.push_back(std::move(item));
  return plan;
}

}  // namespace spectralize
