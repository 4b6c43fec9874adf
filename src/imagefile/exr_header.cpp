#include "imagefile/exr_header.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <vector>

namespace spectralize {

namespace {

enum class Parse { complete, incomplete, malformed };

// Parses "magic version (name\0 type\0 size value)* \0" from the first `got` bytes of `b`.
// Also records where each attribute's value lies (`extents`) and the double-typed ones.
Parse parse_header(const std::vector<char>& b, std::size_t got,
                   std::map<std::string, std::string>& out,
                   std::map<std::string, std::pair<std::uint64_t, std::uint64_t>>* extents,
                   std::map<std::string, double>* doubles,
                   std::map<std::string, std::array<std::int32_t, 4>>* boxes) {
  const unsigned char magic[4] = {0x76, 0x2f, 0x31, 0x01};
  if (got < 8) return Parse::incomplete;
  if (std::memcmp(b.data(), magic, 4) != 0) return Parse::malformed;
  if (b[5] & 0x10) return Parse::malformed;  // multi-part: not what spectralize writes
  std::size_t at = 8;
  // A NUL-terminated name of at most 255 bytes.
  auto text = [&](std::string& s) {
    const void* end = std::memchr(b.data() + at, 0, std::min<std::size_t>(got - at, 256));
    if (!end) return got - at < 256 ? Parse::incomplete : Parse::malformed;
    const std::size_t n = static_cast<std::size_t>(static_cast<const char*>(end) - (b.data() + at));
    s.assign(b.data() + at, n);
    at += n + 1;
    return Parse::complete;
  };
  while (at < got) {
    std::string name, type;
    if (Parse p = text(name); p != Parse::complete) return p;
    if (name.empty()) return Parse::complete;  // the end of the header
    if (Parse p = text(type); p != Parse::complete) return p;
    if (at + 4 > got) return Parse::incomplete;
    std::uint32_t size;
    std::memcpy(&size, b.data() + at, 4);  // little-endian, as OpenEXR stores it
    at += 4;
    if (size > got - at) return Parse::incomplete;
    if (type == "string") out[name] = std::string(b.data() + at, size);
    if (type == "double" && size == 8 && doubles) {
      double v;
      std::memcpy(&v, b.data() + at, 8);  // little-endian, as OpenEXR stores it
      (*doubles)[name] = v;
    }
    if (type == "box2i" && size == 16 && boxes) {
      std::array<std::int32_t, 4> v;
      std::memcpy(v.data(), b.data() + at, 16);  // xMin, yMin, xMax, yMax, little-endian
      (*boxes)[name] = v;
    }
    if (extents) (*extents)[name] = {at, size};
    at += size;
  }
  return Parse::incomplete;
}

}  // namespace

namespace {

// Reads the header of `path` (64 KB, more only if it goes on, up to 1 MB) and parses it.
bool read_header(const std::string& path, std::map<std::string, std::string>& out,
                 std::map<std::string, std::pair<std::uint64_t, std::uint64_t>>* extents,
                 std::map<std::string, double>* doubles = nullptr,
                 std::map<std::string, std::array<std::int32_t, 4>>* boxes = nullptr) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return false;
  std::vector<char> b;
  std::size_t got = 0;
  bool complete = false;
  for (std::size_t size = 1 << 16; size <= (1u << 20); size *= 4) {
    b.resize(size);
    while (got < size) {
      const ssize_t n = ::read(fd, b.data() + got, size - got);
      if (n <= 0) break;
      got += static_cast<std::size_t>(n);
    }
    out.clear();
    if (extents) extents->clear();
    if (doubles) doubles->clear();
    if (boxes) boxes->clear();
    const Parse p = parse_header(b, got, out, extents, doubles, boxes);
    complete = p == Parse::complete;
    if (complete || p == Parse::malformed || got < size) break;  // done, garbage, or cut short
  }
  ::close(fd);
  if (!complete) {
    out.clear();
    if (extents) extents->clear();
    if (doubles) doubles->clear();
    if (boxes) boxes->clear();
  }
  return complete;
}

}  // namespace

std::map<std::string, std::string> exr_string_attributes(const std::string& path) {
  std::map<std::string, std::string> out;
  read_header(path, out, nullptr);
  return out;
}

ExrHeaderValues exr_header_values(const std::string& path) {
  ExrHeaderValues v;
  read_header(path, v.strings, nullptr, &v.doubles, &v.boxes);
  return v;
}

std::map<std::string, std::pair<std::uint64_t, std::uint64_t>> exr_attribute_extents(
    const std::string& path) {
  std::map<std::string, std::string> values;
  std::map<std::string, std::pair<std::uint64_t, std::uint64_t>> extents;
  read_header(path, values, &extents);
  return extents;
}

}  // namespace spectralize
