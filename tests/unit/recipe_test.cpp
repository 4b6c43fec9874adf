// Recipes (settings/recipe.h): what they accept and refuse, by the one settings schema, and the
// chain of recipes a thread is opening (loops and depth). Oracle: the schema's documented
// values and the messages the guide quotes.

#include "settings/recipe.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <memory>

#include "file_test_support.h"
#include "spectralize/core/error.h"

namespace fs = std::filesystem;

namespace spectralize {
namespace {

TEST(Recipe, ParsesEveryKeyByTheSchemaAndResolvesTheSource) {
  const Recipe r = parse_recipe(
      R"({"source": "img/a.png", "mode": "reflectance", "wavelengths": "400:700:10",
          "tile": 64, "filter": 0.5, "format": "float", "model": "smooth"})",
      "/recipes/x.spectral");
  EXPECT_EQ(r.source, "/recipes/img/a.png");
  EXPECT_FALSE(r.to_rgb);
  EXPECT_EQ(r.settings.mode, ModeChoice::reflectance);
  EXPECT_EQ(r.settings.spectral.grid.size(), 31u);
  EXPECT_EQ(r.settings.tile_width, 64);
  EXPECT_EQ(r.settings.tile_height, 64);
  EXPECT_EQ(r.settings.spectral.filter.to_string(), "0.5");
  EXPECT_FALSE(r.settings.half);
  EXPECT_EQ(r.settings.spectral.model, "smooth");
  // Overrides (the plugin's spectral:<key> attributes) win over the file.
  const Recipe o = parse_recipe(R"({"source": "a.png", "mode": "emission"})", "x.spectral",
                                {{"mode", "reflectance"}});
  EXPECT_EQ(o.settings.mode, ModeChoice::reflectance);
}

TEST(Recipe, RefusesWhatTheCliRefusesNamingTheRecipe) {
  for (const char* text :
       {R"([1, 2])", R"({"source": 3})", R"({"mode": "emission"})", R"({"source": "a", "x": 1})",
        R"({"source": "a", "compression": "bogus"})", R"({"source": "a", "tile": 7})",
        R"({"source": "a", "threads": ""})",
        R"({"source": "a", "to": "rgb", "wavelengths": "400:700:10"})",
        R"({"source": "a", "print_format": "json"})", R"({"source": "a", "to": "cmyk"})",
        R"({"source": "a", "mode": true})", "{not json"}) {
    try {
      parse_recipe(text, "bad.spectral");
      ADD_FAILURE() << "accepted " << text;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("bad.spectral"), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(parse_recipe("{\"source\": \"" + std::string(70000, 'a') + "\"}", "big.spectral"),
               Error);
  EXPECT_TRUE(looks_like_recipe(R"({"source": "a.png"})"));
  EXPECT_FALSE(looks_like_recipe(R"({"source": 1})"));
}

TEST(Recipe, CacheWritesOnlyWhenAsked) {
  EXPECT_FALSE(parse_recipe(R"({"source": "a.png", "cache": "c"})", "x.spectral").cache_write);
  EXPECT_TRUE(
      parse_recipe(R"({"source": "a.png", "cache_write": "yes"})", "x.spectral").cache_write);
  // The plugin's attribute spectral:cache_write arrives as an override.
  EXPECT_TRUE(
      parse_recipe(R"({"source": "a.png"})", "x.spectral", {{"cache_write", "yes"}}).cache_write);
  EXPECT_THROW(parse_recipe(R"({"source": "a.png", "cache_write": "1"})", "x.spectral"), Error);
}

// Recipe chains: a thread's nested opens. Oracle: the documented limit and the file system's
// identity of files (a hard link is the same recipe).
TEST(RecipeChain, RefusesLoopsAndChainsBeyondTheLimitNamingTheFirstRecipe) {
  const test::TempDir t("recipe_chain");
  const fs::path& dir = t.dir;
  std::vector<std::string> paths;
  for (int i = 0; i <= kMaxRecipeDepth; ++i) {
    std::string name = "r";  // appended: GCC 12 warns falsely on "r" + std::string
    name += std::to_string(i);
    name += ".spectral";
    paths.push_back((dir / name).string());
    std::ofstream(paths.back()) << "{}";
  }
  {
    std::vector<std::unique_ptr<RecipeChainLink>> links;
    for (int i = 0; i < kMaxRecipeDepth; ++i) {
      links.push_back(std::make_unique<RecipeChainLink>(paths[i]));
      EXPECT_EQ(links.back()->depth(), i + 1);
    }
    try {
      RecipeChainLink one_more(paths[kMaxRecipeDepth]);
      ADD_FAILURE() << "a chain of " << kMaxRecipeDepth + 1 << " recipes was accepted";
    } catch (const Error& e) {
      const std::string m = e.what();
      EXPECT_EQ(m.rfind("'" + paths[0] + "': a chain of more than 16 recipes", 0), 0u) << m;
      EXPECT_EQ(RecipeChainLink::chain_failure(), m);
    }
  }
  {
    // A loop through another name of the same file; a fresh chain forgets the old failure.
    const std::string alias = (dir / "alias.spectral").string();
    fs::create_hard_link(paths[0], alias);
    RecipeChainLink a(paths[0]);
    EXPECT_TRUE(RecipeChainLink::chain_failure().empty());
    RecipeChainLink b(paths[1]);
    try {
      RecipeChainLink again(alias);
      ADD_FAILURE() << "a loop was accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("loop"), std::string::npos) << e.what();
    }
  }
  // Every link has gone: the chain starts again at depth 1.
  EXPECT_EQ(RecipeChainLink(paths[3]).depth(), 1);
}

}  // namespace
}  // namespace spectralize
