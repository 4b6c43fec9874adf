#include "text/strings.h"

#include <cinttypes>
#include <cstdio>

#include "spectralize/core/error.h"
#include "spectralize/rt.hpp"

namespace spectralize {

std::string clip(std::string_view value, std::size_t limit) {
  if (value.size() <= limit) return std::string(value);
  std::size_t n = limit;
  while (n > 0 && (static_cast<unsigned char>(value[n]) & 0xC0) == 0x80) --n;
  return std::string(value.substr(0, n)) + "... (" + std::to_string(value.size()) + " bytes)";
}

std::string quoted_path(std::string_view path) {
  return quote(path, 200);
}

// One implementation: the render-time evaluator's, which checks table files with it.
std::uint64_t fnv1a(std::string_view bytes) {
  return fnv1a(bytes, spz::detail::kFnv1aOffsetBasis);
}

std::uint64_t fnv1a(std::string_view bytes, std::uint64_t h) {
  return spz::detail::fnv1a(reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size(), h);
}

std::string hex64(std::uint64_t v) {
  char buf[24];
  std::snprintf(buf, sizeof buf, "%016" PRIx64, v);
  return buf;
}

}  // namespace spectralize
