#include "io/recipe.h"

#include <charconv>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "core/colorimetry.h"
#include "core/edge_filter.h"
#include "core/error.h"
#include "core/wavelength_grid.h"

namespace spectralize {

namespace {

using Json = nlohmann::json;

const char* const kKeys[] = {"source",   "to",          "colorspace", "mode",   "wavelengths",
                             "observer", "illuminant",  "filter",     "model",  "emission_basis",
                             "format",   "compression", "tile",       "method", "cache",
                             "threads",  "config"};

int as_int(const std::string& key, const std::string& value, int lo, int hi) {
  int v = 0;
  auto r = std::from_chars(value.data(), value.data() + value.size(), v);
  if (value.empty() || r.ec != std::errc() || r.ptr != value.data() + value.size() || v < lo ||
      v > hi)
    throw Error("key '" + key + "': '" + value + "' is not a whole number in " +
                std::to_string(lo) + ".." + std::to_string(hi));
  return v;
}

}  // namespace

bool looks_like_recipe(const std::string& text) {
  Json j = Json::parse(text, nullptr, /*allow_exceptions=*/false);
  return j.is_object() && j.contains("source") && j["source"].is_string();
}

Recipe parse_recipe(const std::string& text, const std::string& path,
                    const std::map<std::string, std::string>& overrides) {
  const std::string where = "'" + path + "': ";
  Json j = Json::parse(text, nullptr, false);
  if (j.is_discarded()) {
    // Parse again to get the parser's own words about where it failed.
    try {
      Json again = Json::parse(text);
      (void)again;
    } catch (const Json::exception& e) {  // parse errors, and numbers out of range
      throw Error(where + "invalid JSON: " + e.what());
    }
    throw Error(where + "invalid JSON");
  }
  if (!j.is_object()) throw Error(where + "a recipe is a JSON object {\"source\": ...}");

  // Every value as text (numbers allowed where the CLI takes numbers), then the overrides.
  std::map<std::string, std::string> v;
  for (auto it = j.begin(); it != j.end(); ++it) {
    bool known = false;
    for (const char* k : kKeys) known = known || it.key() == k;
    if (!known) {
      std::string keys;
      for (const char* k : kKeys) keys += (keys.empty() ? "" : ", ") + std::string(k);
      throw Error(where + "unknown key '" + it.key() + "' (valid: " + keys + ")");
    }
    const bool numeric = it.key() == "tile" || it.key() == "threads" || it.key() == "filter";
    if (it->is_string())
      v[it.key()] = it->get<std::string>();
    else if (!numeric)
      throw Error(where + "key '" + it.key() + "': expected a string");
    else if (it->is_number_integer())
      v[it.key()] = std::to_string(it->get<long long>());
    else if (it->is_number())
      v[it.key()] = it->dump();
    else
      throw Error(where + "key '" + it.key() + "': expected a string or a number");
  }
  for (const auto& [key, value] : overrides) v[key] = value;
  if (!v.count("source") || v["source"].empty()) throw Error(where + "no \"source\" given");

  Recipe r;
  namespace fs = std::filesystem;
  fs::path source(v["source"]);
  if (source.is_relative()) source = fs::path(path).parent_path() / source;
  r.source = source.lexically_normal().string();
  try {
    const std::string to = v.count("to") ? v["to"] : "spectral";
    if (to != "spectral" && to != "rgb")
      throw Error("key 'to': '" + to + "' (valid: spectral, rgb)");
    r.to_rgb = to == "rgb";
    auto get = [&](const char* key, const std::string& fallback) {
      return v.count(key) ? v[key] : fallback;
    };
    const std::string format = get("format", "half");
    if (format != "half" && format != "float")
      throw Error("key 'format': '" + format + "' (valid: half, float)");
    const int threads = v.count("threads") ? as_int("threads", v["threads"], 1, 1024) : 0;
    // Names are checked here, so a bad recipe fails at open().
    const std::string observer = get("observer", "cie1931");
    const std::string illuminant = get("illuminant", "D65");
    try {
      Observer::get(observer);
    } catch (const Error& e) {
      throw Error(std::string("key 'observer': ") + e.what());
    }
    try {
      Illuminant::get(illuminant);
    } catch (const Error& e) {
      throw Error(std::string("key 'illuminant': ") + e.what());
    }
    if (r.to_rgb) {
      for (const char* spectral_only :
           {"mode", "wavelengths", "filter", "model", "emission_basis", "method", "cache", "tile"})
        if (v.count(spectral_only))
          throw Error("key '" + std::string(spectral_only) + "' does not apply to \"to\": \"rgb\"");
      ToRgbSettings& s = r.rgb;
      s.input = r.source;
      s.colorspace = get("colorspace", "Linear Rec.709 (sRGB)");
      s.observer = observer;
      s.illuminant = illuminant;
      s.half = format == "half";
      s.compression = get("compression", "zip");
      s.threads = threads;
      s.config = get("config", "");
    } else {
      ImageJobSettings& s = r.spectral;
      s.input = r.source;
      s.colorspace = get("colorspace", "");
      s.mode = get("mode", "auto");
      if (s.mode != "auto" && s.mode != "emission" && s.mode != "reflectance")
        throw Error("key 'mode': '" + s.mode + "' (valid: auto, emission, reflectance)");
      try {
        s.spectral.grid = WavelengthGrid::parse(get("wavelengths", "380:780:5"));
      } catch (const Error& e) {
        throw Error(std::string("key 'wavelengths': ") + e.what());
      }
      s.spectral.observer = observer;
      s.spectral.illuminant = illuminant;
      if (v.count("filter")) {
        try {
          s.spectral.filter = EdgeFilter::parse(v["filter"]);
        } catch (const Error& e) {
          throw Error(std::string("key 'filter': ") + e.what());
        }
      }
      try {
        s.spectral.model = parse_model(get("model", "paper"));
      } catch (const Error& e) {
        throw Error(std::string("key 'model': ") + e.what());
      }
      try {
        s.spectral.emission_basis = parse_emission_basis(get("emission_basis", "flat"));
      } catch (const Error& e) {
        throw Error(std::string("key 'emission_basis': ") + e.what());
      }
      s.half = format == "half";
      s.compression = get("compression", "zip");
      s.tile = v.count("tile") ? as_int("tile", v["tile"], 16, 4096) : 0;
      const std::string method = get("method", "table");
      if (method != "table" && method != "exact")
        throw Error("key 'method': '" + method + "' (valid: table, exact)");
      s.method = method == "table" ? SpectralTable::Method::table : SpectralTable::Method::exact;
      s.cache_dir = get("cache", "");
      s.threads = threads;
      s.config = get("config", "");
    }
  } catch (const Error& e) {
    throw Error(where + e.what());
  }
  return r;
}

}  // namespace spectralize
