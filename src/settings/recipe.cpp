#include "settings/recipe.h"

#include <sys/stat.h>

#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <utility>
#include <vector>

#include "spectralize/core/error.h"
#include "text/strings.h"

namespace spectralize {

namespace {

using Json = nlohmann::json;

// The keys a recipe of this direction accepts: "source", "to", "cache_write" and the schema's.
std::string valid_keys(Command command) {
  std::string keys = "source, to, cache_write";
  for (const SettingSpec& s : settings_schema())
    if (s.recipe && s.applies(command)) keys += ", " + std::string(s.key);
  return keys;
}

// This thread's chain of recipes being opened (RecipeChainLink), and the first failure of it.
struct Chain {
  std::vector<std::pair<std::string, std::pair<dev_t, ino_t>>> links;  // path, file identity
  std::string failure;
};
thread_local Chain t_chain;

std::string chain_text(const std::vector<std::string>& paths) {
  // The first two and the last: enough to find the chain, short enough to read.
  std::string text;
  for (std::size_t i = 0; i < paths.size(); ++i) {
    if (i >= 2 && i + 1 < paths.size()) {
      if (i == 2) text += " -> ...";
      continue;
    }
    text += (i ? " -> '" : "'") + clip(paths[i], 120) + "'";
  }
  return text;
}

}  // namespace

int max_recipe_depth() {
  if (const char* v = std::getenv("SPECTRALIZE_TEST_RECIPE_DEPTH"); v && *v) {
    char* end = nullptr;
    const long n = std::strtol(v, &end, 10);
    if (*end == '\0' && n > kMaxRecipeDepth && n < 1000000) return static_cast<int>(n);
  }
  return kMaxRecipeDepth;
}

RecipeChainLink::RecipeChainLink(const std::string& path) {
  Chain& c = t_chain;
  struct stat st = {};
  const bool known = ::stat(path.c_str(), &st) == 0;
  const std::pair<dev_t, ino_t> id{known ? st.st_dev : 0, known ? st.st_ino : 0};
  std::vector<std::string> paths;
  for (const auto& link : c.links) paths.push_back(link.first);
  paths.push_back(path);
  const std::string first = quote(paths.front(), 200) + ": ";
  for (const auto& link : c.links)
    if (known && link.second == id) {
      c.failure = first + "the recipes form a loop (" + chain_text(paths) +
                  "): a recipe's source leads back to a recipe of the chain";
      throw Error(c.failure);
    }
  const int limit = max_recipe_depth();
  if (static_cast<int>(paths.size()) > limit) {
    c.failure = first + "a chain of more than " + std::to_string(limit) +
                " recipes, each the source of the one before (" + chain_text(paths) +
                "); at most " + std::to_string(limit) + " recipes may lead to an image";
    throw Error(c.failure);
  }
  c.links.emplace_back(path, id);
  c.failure.clear();  // an earlier failure of this thread is not this chain's
  depth_ = static_cast<int>(c.links.size());
}

RecipeChainLink::~RecipeChainLink() {
  t_chain.links.pop_back();
}

const std::string& RecipeChainLink::chain_failure() {
  return t_chain.failure;
}

bool looks_like_recipe(const std::string& text) {
  if (text.size() > kMaxRecipeBytes) return false;
  Json j = Json::parse(text, nullptr, /*allow_exceptions=*/false);
  return j.is_object() && j.contains("source") && j["source"].is_string();
}

Recipe parse_recipe(const std::string& text, const std::string& path,
                    const std::map<std::string, std::string>& overrides) {
  const std::string where = quote(path, 200) + ": ";
  if (text.size() > kMaxRecipeBytes)
    throw Error(where + "too large for a recipe (" + std::to_string(text.size()) +
                " bytes; at most 64 KB)");
  Json j = Json::parse(text, nullptr, false);
  if (j.is_discarded()) {
    // Parse again to get the parser's own words about where it failed.
    try {
      Json again = Json::parse(text);
      (void)again;
    } catch (const Json::exception& e) {  // parse errors, and numbers out of range
      throw Error(where + "invalid JSON: " + clip(e.what(), 200));
    }
    throw Error(where + "invalid JSON");
  }
  if (!j.is_object()) throw Error(where + "a recipe is a JSON object {\"source\": ...}");

  // Every value as text (numbers where the CLI takes numbers are validated like the CLI's
  // text), then the overrides.
  std::map<std::string, std::string> values;
  for (auto it = j.begin(); it != j.end(); ++it) {
    if ((it.key() == "source" || it.key() == "to" || it.key() == "cache_write") && !it->is_string())
      throw Error(where + "key '" + it.key() + "': expected a string");
    if (it->is_string())
      values[it.key()] = it->get<std::string>();
    else if (it->is_number_integer())
      values[it.key()] = std::to_string(it->get<long long>());
    else if (it->is_number())
      values[it.key()] = it->dump();
    else
      throw Error(where + "key '" + clip(it.key()) + "': expected a string or a number");
  }
  for (const auto& [key, value] : overrides) values[key] = value;

  Recipe r;
  const std::string to = values.count("to") ? values["to"] : "spectral";
  if (to != "spectral" && to != "rgb")
    throw Error(where + "key 'to': '" + clip(to) + "' (valid: spectral, rgb)");
  r.to_rgb = to == "rgb";
  if (values.count("cache_write")) {
    const std::string& w = values["cache_write"];
    if (w != "yes" && w != "no")
      throw Error(where + "key 'cache_write': '" + clip(w) + "' (valid: yes, no)");
    r.cache_write = w == "yes";
  }
  const Command command = r.to_rgb ? kToRgb : kImage;
  for (const auto& [key, value] : values) {
    if (key == "source" || key == "to" || key == "cache_write") continue;
    const SettingSpec* spec = find_setting(key);
    if (!spec || !spec->recipe || !spec->applies(command)) {
      const bool other = spec && spec->recipe;
      throw Error(where +
                  (other ? "key '" + clip(key) + "' does not apply to \"to\": \"" + to + "\""
                         : "unknown key '" + clip(key) + "' (valid: " + valid_keys(command) + ")"));
    }
    apply_setting(r.settings, *spec, value, where + "key '" + key + "'");
  }
  if (!values.count("source") || values["source"].empty())
    throw Error(where + "no \"source\" given");
  namespace fs = std::filesystem;
  fs::path source(values["source"]);
  if (source.is_relative()) source = fs::path(path).parent_path() / source;
  r.source = source.lexically_normal().string();
  return r;
}

}  // namespace spectralize
