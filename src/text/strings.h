#pragma once
// Short texts for messages, and the 64-bit hash names and keys are made of: one place for what
// every layer needs to name a file or a value without echoing a megabyte back.

#include <cstdint>
#include <string>
#include <string_view>

namespace spectralize {

/// Shortens a user-supplied value for a message: at most `limit` bytes (whole UTF-8
/// characters), then "... (N bytes)". Cost: O(limit).
std::string clip(std::string_view value, std::size_t limit = 80);

/// A path quoted for a message, shortened to 200 bytes: "'lib/a.png'". Cost: O(200).
std::string quoted_path(std::string_view path);

/// The standard FNV-1a (64-bit) of `bytes`: stable across machines and standard libraries, so
/// usable in file names and keys. Cost: O(bytes).
std::uint64_t fnv1a(std::string_view bytes);
/// FNV-1a of `bytes` continuing the hash `h` of what came before them. Cost: O(bytes).
std::uint64_t fnv1a(std::string_view bytes, std::uint64_t h);

/// `v` as 16 lower-case hexadecimal digits. Cost: O(1).
std::string hex64(std::uint64_t v);

}  // namespace spectralize
