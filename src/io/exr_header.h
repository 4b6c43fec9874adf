#pragma once
// The string attributes of an OpenEXR header, read directly from the file's first bytes: what
// ingest needs to tell in microseconds whether an output is up to date (OIIO's full open costs
// far more). Bounds-checked: a truncated or foreign file gives an empty map, never a crash.

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <utility>

namespace spectralize {

/// The string-typed attributes of the first part of the OpenEXR file at `path` (name -> value);
/// empty if the file is missing, not OpenEXR, multi-part or malformed. Reads at most 1 MB.
/// Cost: one open and read of the header, ~10-50 us.
std::map<std::string, std::string> exr_string_attributes(const std::string& path);

/// Where the value of the string attribute `name` lies in the OpenEXR file at `path`: (byte
/// offset, size), or nullopt when the header is unreadable or has no such attribute. Cost: as
/// exr_string_attributes.
std::optional<std::pair<std::uint64_t, std::uint64_t>> exr_string_attribute_extent(
    const std::string& path, const std::string& name);

}  // namespace spectralize
