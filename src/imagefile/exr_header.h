#pragma once
// The string attributes of an OpenEXR header, read directly from the file's first bytes: what
// ingest needs to tell in microseconds whether an output is up to date (OIIO's full open costs
// far more). Bounds-checked: a truncated or foreign file gives an empty map, never a crash.

#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <utility>

namespace spectralize {

/// The string-typed attributes of the first part of the OpenEXR file at `path` (name -> value);
/// empty if the file is missing, not OpenEXR, multi-part or malformed. Reads at most 1 MB.
/// Cost: one open and read of the header, ~10-50 us.
std::map<std::string, std::string> exr_string_attributes(const std::string& path);

/// The string, double and box2i (xMin, yMin, xMax, yMax: dataWindow, displayWindow) attributes
/// of the header, as exr_string_attributes reads them.
struct ExrHeaderValues {
  std::map<std::string, std::string> strings;
  std::map<std::string, double> doubles;
  std::map<std::string, std::array<std::int32_t, 4>> boxes;
};
ExrHeaderValues exr_header_values(const std::string& path);

/// Where the value of each attribute (any type) lies in the OpenEXR file at `path`: name ->
/// (byte offset, size); empty when the header is unreadable. Cost: as exr_string_attributes.
std::map<std::string, std::pair<std::uint64_t, std::uint64_t>> exr_attribute_extents(
    const std::string& path);

/// Why the file at `path` is not a whole single-part scanline OpenEXR of `width` x `height`
/// pixels and `channels` channels, or "" when it is: its header complete, its data window and
/// channel list that size, one line offset per block of its compression, each pointing at a
/// chunk of that block inside the file, the chunks ending at the file's last byte. What a writer
/// checks before renaming what it wrote. Cost: one header read and an 8-byte read per block.
std::string exr_scanline_problem(const std::string& path, int width, int height, int channels);

}  // namespace spectralize
