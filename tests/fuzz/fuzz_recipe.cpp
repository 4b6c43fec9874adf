// libFuzzer target: the .spectral recipe parser (untrusted JSON from disk). Any input must
// either parse into a recipe or throw spectralize::Error; nothing else.
#include <cstddef>
#include <cstdint>
#include <string>

#include "settings/recipe.h"
#include "spectralize/core/error.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  (void)spectralize::looks_like_recipe(text);
  try {
    spectralize::Recipe r = spectralize::parse_recipe(text, "/fuzz/recipe.spectral");
    if (r.source.empty()) __builtin_trap();  // a parsed recipe always names its source
  } catch (const spectralize::Error&) {
  }
  return 0;
}
