#pragma once
// ".spectral" recipes: small JSON files that tell the OpenImageIO plugin what to present, e.g.
//   {"source": "albedo.png", "colorspace": "sRGB - Texture", "mode": "reflectance",
//    "wavelengths": "380:780:10"}                                  (RGB -> spectral)
//   {"source": "x.exr", "to": "rgb", "colorspace": "ACEScg", "illuminant": "A"}  (spectral -> RGB)
// Every setting of the CLI's image (or --to-rgb) command may appear, by its schema key and with
// the CLI's validation (io/settings.h); `source` is relative to the recipe.

#include <cstddef>
#include <map>
#include <string>

#include "io/settings.h"

namespace spectralize {

/// The largest recipe accepted, in bytes (a recipe is a few hundred).
inline constexpr std::size_t kMaxRecipeBytes = 64 * 1024;

struct Recipe {
  std::string source;   // resolved against the recipe's folder
  bool to_rgb = false;  // "to": "spectral" (default) or "rgb"
  Settings settings;
};

/// Parses a recipe's text; `path` names it in messages and anchors a relative source. Extra
/// options (e.g. the plugin's "spectral:<key>" attributes, without the prefix) override the
/// file's. Throws Error "'<path>': <problem>" for text over kMaxRecipeBytes, invalid JSON, a
/// non-object, unknown keys (or keys of the other direction), values of the wrong type or
/// refused by the schema, or a missing source. Cost: O(text).
Recipe parse_recipe(const std::string& text, const std::string& path,
                    const std::map<std::string, std::string>& overrides = {});

/// Quick and strict check that `text` looks like a recipe: a JSON object with a string
/// "source", at most kMaxRecipeBytes. Never throws. Cost: O(text).
bool looks_like_recipe(const std::string& text);

}  // namespace spectralize
