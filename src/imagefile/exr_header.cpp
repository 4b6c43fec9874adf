#include "imagefile/exr_header.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <vector>

#include "imagefile/openexr_compat.h"

namespace spectralize {

namespace {

enum class Parse { complete, incomplete, malformed };

// What the structure check needs of a header besides its values.
struct Layout {
  std::size_t end = 0;   // the offset just past the header's terminating NUL
  int channels = -1;     // entries of the "channels" list
  int compression = -1;  // the "compression" byte
  bool tiled = false;    // a "tiles" attribute
};

// The entries of a chlist value: (name\0, pixel type, pLinear, 3 reserved, x and y sampling)*,
// then \0; -1 when malformed.
int chlist_entries(const char* v, std::size_t size) {
  int n = 0;
  std::size_t at = 0;
  while (at < size && v[at] != 0) {
    const void* end = std::memchr(v + at, 0, size - at);
    if (!end) return -1;
    at = static_cast<std::size_t>(static_cast<const char*>(end) - v) + 1 + 16;
    ++n;
  }
  return at + 1 == size ? n : -1;
}

// Parses "magic version (name\0 type\0 size value)* \0" from the first `got` bytes of `b`.
// Also records where each attribute's value lies (`extents`), the double-typed ones and what a
// structure check needs (`layout`).
Parse parse_header(const std::vector<char>& b, std::size_t got,
                   std::map<std::string, std::string>& out,
                   std::map<std::string, std::pair<std::uint64_t, std::uint64_t>>* extents,
                   std::map<std::string, double>* doubles,
                   std::map<std::string, std::array<std::int32_t, 4>>* boxes,
                   Layout* layout = nullptr) {
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
    if (name.empty()) {  // the end of the header
      if (layout) layout->end = at;
      return Parse::complete;
    }
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
    if (layout && type == "chlist") layout->channels = chlist_entries(b.data() + at, size);
    if (layout && type == "compression" && size == 1)
      layout->compression = static_cast<unsigned char>(b[at]);
    if (layout && type == "tiledesc") layout->tiled = true;
    at += size;
  }
  return Parse::incomplete;
}

}  // namespace

namespace {

// Reads the header of the file open as `fd` (64 KB, more only if it goes on, up to 1 MB) and
// parses it.
bool read_header(int fd, std::map<std::string, std::string>& out,
                 std::map<std::string, std::pair<std::uint64_t, std::uint64_t>>* extents,
                 std::map<std::string, double>* doubles = nullptr,
                 std::map<std::string, std::array<std::int32_t, 4>>* boxes = nullptr,
                 Layout* layout = nullptr) {
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
    const Parse p = parse_header(b, got, out, extents, doubles, boxes, layout);
    complete = p == Parse::complete;
    if (complete || p == Parse::malformed || got < size) break;  // done, garbage, or cut short
  }
  if (!complete) {
    out.clear();
    if (extents) extents->clear();
    if (doubles) doubles->clear();
    if (boxes) boxes->clear();
  }
  return complete;
}

bool read_header(const std::string& path, std::map<std::string, std::string>& out,
                 std::map<std::string, std::pair<std::uint64_t, std::uint64_t>>* extents,
                 std::map<std::string, double>* doubles = nullptr,
                 std::map<std::string, std::array<std::int32_t, 4>>* boxes = nullptr) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return false;
  const bool complete = read_header(fd, out, extents, doubles, boxes);
  ::close(fd);
  return complete;
}

bool read_exact(int fd, void* to, std::size_t n, std::uint64_t at) {
  auto* p = static_cast<char*>(to);
  while (n > 0) {
    const ssize_t got = ::pread(fd, p, n, static_cast<off_t>(at));
    if (got <= 0) return false;
    p += got, at += static_cast<std::uint64_t>(got), n -= static_cast<std::size_t>(got);
  }
  return true;
}

// The structure of a single-part scanline file open as `fd` (docs/DESIGN.md §10): "" or why not.
std::string scanline_problem(int fd, int width, int height, int channels) {
  struct stat st = {};
  if (::fstat(fd, &st) != 0) return "cannot be examined";
  const auto size = static_cast<std::uint64_t>(st.st_size);
  std::map<std::string, std::string> strings;
  std::map<std::string, std::array<std::int32_t, 4>> boxes;
  Layout layout;
  if (!read_header(fd, strings, nullptr, nullptr, &boxes, &layout))
    return "its header is not a whole single-part OpenEXR header";
  if (layout.tiled) return "it is tiled";
  const auto window = boxes.find("dataWindow");
  if (window == boxes.end()) return "its header has no data window";
  const auto [x0, y0, x1, y1] = window->second;
  if (std::int64_t{x1} - x0 + 1 != width || std::int64_t{y1} - y0 + 1 != height)
    return "its data window is " + std::to_string(std::int64_t{x1} - x0 + 1) + "x" +
           std::to_string(std::int64_t{y1} - y0 + 1) + ", not " + std::to_string(width) + "x" +
           std::to_string(height);
  if (layout.channels != channels)
    return "it has " + std::to_string(layout.channels) + " channels, not " +
           std::to_string(channels);
  int rows = 0;
  for (const ExrCompression& c : exr_compressions())
    if (c.id == layout.compression) rows = c.block_rows;
  if (rows <= 0) return "its compression is not one this OpenEXR knows";
  // One offset per block, each at a chunk (y, size, data) of its block inside the file; the
  // chunks end at the file's last byte.
  const std::uint64_t blocks = (static_cast<std::uint64_t>(height) + rows - 1) / rows;
  std::vector<std::uint64_t> offsets(blocks);
  if (!read_exact(fd, offsets.data(), blocks * 8, layout.end))  // little-endian, as stored
    return "its line offset table is cut short";
  const std::uint64_t data_start = layout.end + blocks * 8;
  std::uint64_t last = data_start;
  std::vector<bool> seen(blocks, false);
  for (const std::uint64_t offset : offsets) {
    std::int32_t head[2];
    if (offset < data_start || offset > size - std::min<std::uint64_t>(size, 8) ||
        !read_exact(fd, head, 8, offset))
      return "its line offset table points outside the file";
    const std::int64_t block = (std::int64_t{head[0]} - y0) / rows;
    if (head[0] < y0 || (std::int64_t{head[0]} - y0) % rows != 0 || block >= std::int64_t(blocks) ||
        seen[static_cast<std::size_t>(block)] || head[1] < 0 ||
        offset + 8 + static_cast<std::uint64_t>(head[1]) > size)
      return "a chunk at byte " + std::to_string(offset) + " is not a block of its rows";
    seen[static_cast<std::size_t>(block)] = true;
    last = std::max(last, offset + 8 + static_cast<std::uint64_t>(head[1]));
  }
  if (last != size)
    return "its chunks end at byte " + std::to_string(last) + " of " + std::to_string(size);
  return "";
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

std::string exr_scanline_problem(const std::string& path, int width, int height, int channels) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return "cannot be opened";
  std::string problem = scanline_problem(fd, width, height, channels);
  ::close(fd);
  return problem;
}

}  // namespace spectralize
