#pragma once
// ".spectral" recipes: small JSON files that tell the OpenImageIO plugin what to present, e.g.
//   {"source": "albedo.png", "colorspace": "sRGB - Texture", "mode": "reflectance",
//    "wavelengths": "380:780:10"}                                  (RGB -> spectral)
//   {"source": "x.exr", "to": "rgb", "colorspace": "ACEScg", "illuminant": "A"}  (spectral -> RGB)
// Every option of the CLI may appear as a key; `source` is relative to the recipe.

#include <map>
#include <string>

#include "io/image_job.h"

namespace spectralize {

struct Recipe {
  std::string source;         // resolved against the recipe's folder
  bool to_rgb = false;        // "to": "spectral" (default) or "rgb"
  ImageJobSettings spectral;  // for RGB -> spectral (input = source)
  ToRgbSettings rgb;          // for spectral -> RGB (input = source)
};

/// Parses a recipe's text; `path` names it in messages and anchors a relative source. Extra
/// options (e.g. the plugin's "spectral:<key>" attributes, without the prefix) override the
/// file's. Throws Error "'<path>': <problem>" for invalid JSON, a non-object, unknown keys,
/// values of the wrong type or out of range, or a missing source key. Cost: O(text).
Recipe parse_recipe(const std::string& text, const std::string& path,
                    const std::map<std::string, std::string>& overrides = {});

/// Quick and strict check that `text` looks like a recipe: a JSON object with a string
/// "source". Never throws. Cost: O(text).
bool looks_like_recipe(const std::string& text);

}  // namespace spectralize
