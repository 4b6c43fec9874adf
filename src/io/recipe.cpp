#include "io/recipe.h"

#include <filesystem>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "io/safe_output.h"

namespace spectralize {

namespace {

using Json = nlohmann::json;

// The keys a recipe of this direction accepts: "source", "to" and the schema's.
std::string valid_keys(Command command) {
  std::string keys = "source, to";
  for (const SettingSpec& s : settings_schema())
    if (s.recipe && s.applies(command)) keys += ", " + std::string(s.key);
  return keys;
}

}  // namespace

bool looks_like_recipe(const std::string& text) {
  if (text.size() > kMaxRecipeBytes) return false;
  Json j = Json::parse(text, nullptr, /*allow_exceptions=*/false);
  return j.is_object() && j.contains("source") && j["source"].is_string();
}

Recipe parse_recipe(const std::string& text, const std::string& path,
                    const std::map<std::string, std::string>& overrides) {
  const std::string where = "'" + clip(path, 200) + "': ";
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
    if ((it.key() == "source" || it.key() == "to") && !it->is_string())
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
  const Command command = r.to_rgb ? kToRgb : kImage;
  for (const auto& [key, value] : values) {
    if (key == "source" || key == "to") continue;
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
