#pragma once
// ".spectral" recipes: small JSON files that tell the OpenImageIO plugin what to present, e.g.
//   {"source": "albedo.png", "colorspace": "sRGB - Texture", "mode": "reflectance",
//    "wavelengths": "380:780:10"}                                  (RGB -> spectral)
//   {"source": "x.exr", "to": "rgb", "colorspace": "ACEScg", "illuminant": "A"}  (spectral -> RGB)
// Every setting of the CLI's image (or --to-rgb) command may appear, by its schema key and with
// the CLI's validation (settings/settings.h); `source` is relative to the recipe.

#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include "settings/settings.h"

namespace spectralize {

/// The largest recipe accepted, in bytes (a recipe is a few hundred).
inline constexpr std::size_t kMaxRecipeBytes = 64 * 1024;

/// The longest chain of recipes a reader follows: a recipe whose source is a recipe whose source
/// is ... (at most 16 recipes, the first included, before an image). Deeper chains are refused
/// at open with an error naming the chain's first recipe (docs/DESIGN.md §9).
inline constexpr int kMaxRecipeDepth = 16;

struct Recipe {
  std::string source;        // resolved against the recipe's folder
  bool to_rgb = false;       // "to": "spectral" (default) or "rgb"
  bool cache_write = false;  // "cache_write": "yes" lets the reader save the node cache
  Settings settings;
};

/// Parses a recipe's text; `path` names it in messages and anchors a relative source. Extra
/// options (e.g. the plugin's "spectral:<key>" attributes, without the prefix) override the
/// file's. Throws Error "'<path>': <problem>" for text over kMaxRecipeBytes, invalid JSON, a
/// non-object, unknown keys (or keys of the other direction), values of the wrong type or
/// refused by the schema, or a missing source. Cost: O(text).
Recipe parse_recipe(const std::string& text, const std::string& path,
                    const std::map<std::string, std::string>& overrides = {});

/// The chain limit in force: kMaxRecipeDepth, unless the environment variable
/// SPECTRALIZE_TEST_RECIPE_DEPTH raises it (only the tests do, to provoke a stack overflow).
/// Cost: one getenv.
int max_recipe_depth();

/// The recipes this thread is opening, outermost first: a recipe's reader opens its source on
/// the same thread, so nested opens form the chain. Entering a recipe that is already in the
/// chain (the same file under any name, hard links included) or one more than
/// max_recipe_depth() throws Error naming the chain's first recipe and the limit; that message
/// is also what every outer recipe of the chain reports (chain_failure()), so it arrives whole
/// instead of nested once per level. Cost: a stat and O(depth).
class RecipeChainLink {
 public:
  explicit RecipeChainLink(const std::string& path);
  ~RecipeChainLink();
  RecipeChainLink(const RecipeChainLink&) = delete;
  RecipeChainLink& operator=(const RecipeChainLink&) = delete;

  /// Recipes in the chain, this one included (1: the outermost). Cost: O(1).
  int depth() const { return depth_; }
  /// The loop or depth error met by an inner recipe of this thread's chain, or "". Cost: O(1).
  static const std::string& chain_failure();

 private:
  int depth_ = 0;
};

/// Quick and strict check that `text` looks like a recipe: a JSON object with a string
/// "source", at most kMaxRecipeBytes. Never throws. Cost: O(text).
bool looks_like_recipe(const std::string& text);

}  // namespace spectralize
