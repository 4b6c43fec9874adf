#include "imagefile/output_formats.h"

#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <set>

#include "imagefile/oiio_compat.h"
#include "imagefile/openexr_compat.h"
#include "spectralize/core/error.h"
#include "text/strings.h"

namespace spectralize {

namespace {

using Slot = ColourSlot;

// The stated facts about OIIO 2.4's and 3.1's writers, each checked by the unit test against
// files OIIO writes and reads back (tests/unit/output_formats_test.cpp), in both lanes. Samples:
// the types a file keeps as given (others are converted by the writer: uint16 to uint8, half to
// float, ...). Where the two differ, oiio_compat.h says which this build has.
std::vector<OutputFormat> stated_facts() {
  const CompressionChoice zip9{"zip", 1, 9};
  std::vector<OutputFormat> t;
  auto add = [&](OutputFormat f) { t.push_back(std::move(f)); };
  {
    OutputFormat f{"openexr", "OpenEXR", ".exr", {"half", "float"}};
    // Every compression this OpenEXR has (3.4: the lossless HTJ2K too); zip's and zips' level,
    // DWA's quality.
    for (const ExrCompression& c : exr_compressions()) {
      CompressionChoice choice{c.name, 0, 0, false, c.lossy};
      if (c.name == "zip" || c.name == "zips") choice.min_level = 1, choice.max_level = 9;
      if (c.name == "dwaa" || c.name == "dwab") choice.quality = true;
      f.compressions.push_back(choice);
    }
    f.default_compression = "zip";
    f.colour = Slot::attributes;
    f.tile_multiple = 1;
    f.max_tile_bytes = INT_MAX;  // OpenEXR refuses a tile of more uncompressed bytes
    add(f);
  }
  {
    OutputFormat f{"tiff", "TIFF", ".tif", {"uint8", "uint16", "float"}};
    // "jpeg" is left out: lossy, 8-bit 3-channel only, and silently zip for float samples.
    // OIIO 3 compresses TIFF strips itself, at one zip level whatever is asked.
    f.compressions = {{"none"},
                      {"lzw"},
                      oiio_compat::kTiffZipLevels ? zip9 : CompressionChoice{"zip"},
                      {"packbits"}};
    f.default_compression = "zip";
    f.colour = Slot::icc_profile;
    f.tile_multiple = 16;  // libtiff's rule
    add(f);
  }
  {
    OutputFormat f{"png", "PNG", ".png", {"uint8", "uint16"}};
    f.compressions = {{"zip", 0, 9}};  // deflate level, png:compressionLevel (always lossless)
    f.default_compression = "zip:6";
    f.colour = Slot::icc_profile;
    add(f);
  }
  {
    OutputFormat f{"jpeg", "JPEG", ".jpg", {"uint8"}};
    f.compressions = {{"jpeg", 1, 100, false, true}};  // quality
    f.default_compression = "jpeg:98";
    f.colour = Slot::icc_profile;
    add(f);
  }
  {
    OutputFormat f{"hdr", "Radiance HDR", ".hdr", {"float"}};  // RGBE: 8-bit mantissas
    f.default_compression = "rle";
    f.colour = Slot::linear_rec709;
    add(f);
  }
  {
    OutputFormat f{"webp", "WebP", ".webp", {"uint8"}};
    f.compressions = {{"webp", 1, 100, false, true}};  // quality; always lossy through OIIO 2.4
    f.default_compression = "webp:100";
    add(f);
  }
  {
    OutputFormat f{"heif", "HEIF", ".heic", {"uint8"}};
    if (oiio_compat::kHeifHoldsUint16) f.samples.push_back("uint16");
    f.compressions = {{"heic", 1, 100, false, true}, {"avif", 1, 100, false, true}};
    f.default_compression = "heic:50";  // unasked; "heic" alone is 75
    add(f);
  }
  {
    // OIIO 3 writes JPEG XL: every sample type; lossless unasked and at quality 100.
    OutputFormat f{"jpegxl", "JPEG XL", ".jxl", {"uint8", "uint16", "half", "float"}};
    f.compressions = {{"jpegxl", 1, 100}};
    f.default_compression = "jpegxl";
    f.colour = Slot::icc_profile;
    add(f);
  }
  add(OutputFormat{"dpx", "DPX", ".dpx", {"uint8", "uint16", "float"}, {}, "none"});
  add(OutputFormat{"targa", "Targa", ".tga", {"uint8"}, {{"none"}, {"rle"}}, "none"});
  add(OutputFormat{"bmp", "BMP", ".bmp", {"uint8"}, {}, "none"});
  add(OutputFormat{"sgi", "SGI", ".sgi", {"uint8", "uint16"}, {}, "none"});
  add(OutputFormat{"rla", "RLA", ".rla", {"uint8", "uint16", "float"}, {}, "rle"});
  add(OutputFormat{"fits", "FITS", ".fits", {"uint8", "float"}, {}, "none"});
  add(OutputFormat{"pnm",
                   "PNM",
                   ".ppm",
                   oiio_compat::kPnmHoldsUint16AndFloat
                       ? std::vector<std::string_view>{"uint8", "uint16", "float"}
                       : std::vector<std::string_view>{"uint8"},
                   {},
                   "none"});
  // Written by OIIO, not by spectralize: what they store is not what was asked.
  const auto refuse = [&](std::string_view name, std::string_view label, std::string_view why) {
    OutputFormat f{name, label};
    f.refused = why;
    add(f);
  };
  refuse("gif", "GIF",
         "stores a palette of at most 256 colours, and always four channels; write .png");
  refuse("ico", "ICO", "holds icons (8-bit RGBA, at most 256 x 256 pixels); write .png");
  refuse("jpeg2000", "JPEG 2000",
         "files written by OpenImageIO do not read back when a side is under 32 pixels, and "
         "RGBA ones come back with other values (OIIO 2.4 and 3.1); write .png or .tif");
  refuse("iff", "IFF",
         "files are written by OIIO 2.4 in tiles only (its writer refuses scanlines); write "
         ".tif");
  refuse("zfile", "Zfile", "holds one depth channel, not colour; write .exr");
  refuse("null", "null", "writes nothing; write .exr");
  refuse("term", "term", "draws on a terminal, it writes no file; write .png");
  return t;
}

// Why OIIO's writer of `format` cannot write here, or "" when a tiny image writes.
std::string probe_write(const std::string& format, const std::string& extension) {
  std::string dir = "/tmp";
  if (const char* t = std::getenv("TMPDIR"); t && *t) dir = t;
  std::string path = dir + "/spectralize-probe-XXXXXX" + extension;
  const int fd = ::mkstemps(path.data(), static_cast<int>(extension.size()));
  if (fd < 0) return "";  // no place to try: let the real write say what goes wrong
  ::close(fd);
  std::string why;
  auto out = OIIO::ImageOutput::create(format);
  // Room beyond the image: OIIO 2.4's HEIF writer copies each row with libheif's row stride
  // (aligned, 192 bytes for these 24-byte rows), reading past the last row of a tight buffer
  // (AddressSanitizer saw it).
  const std::vector<unsigned char> px(8 * 8 * 3 + 4096, 0);
  if (!out || !out->open(path, OIIO::ImageSpec(8, 8, 3, OIIO::TypeUInt8)) ||
      !out->write_image(OIIO::TypeUInt8, px.data()) || !out->close()) {
    why = out ? out->geterror() : OIIO::geterror();
    if (why.empty()) why = "the writer fails without a reason";
  }
  (void)OIIO::geterror();
  ::unlink(path.c_str());
  return why;
}

// What this OIIO build says about each format: whether it writes it at all, tiles, alpha,
// proxies (each combined with the facts: WebP's "tiles" are emulated, TIFF's proxy writes
// leave unreadable files).
std::vector<OutputFormat> build() {
  std::vector<OutputFormat> t = stated_facts();
  std::string list;
  OIIO::getattribute("output_format_list", list);
  std::set<std::string> writes;
  for (const auto& name : OIIO::Strutil::splits(list, ",")) writes.insert(name);
  for (OutputFormat& f : t) {
    f.available = writes.count(std::string(f.name)) > 0;
    if (!f.available) continue;
    auto out = OIIO::ImageOutput::create(std::string(f.name));
    if (!out) {
      (void)OIIO::geterror();
      f.available = false;
      continue;
    }
    // JPEG drops a fourth channel; FITS keeps it, but not as alpha.
    f.alpha = out->supports("alpha") && f.name != "jpeg" && f.name != "fits";
    f.tiles = out->supports("tiles") && (f.name == "openexr" || f.name == "tiff");
    f.proxy = out->supports("ioproxy") &&
              (f.name == "openexr" || f.name == "png" || f.name == "jpeg" || f.name == "hdr");
  }
  return t;
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// "NAME" or "NAME:LEVEL" -> (NAME, LEVEL text).
std::pair<std::string, std::string> split(const std::string& text) {
  const auto colon = text.find(':');
  return {text.substr(0, colon), colon == std::string::npos ? "" : text.substr(colon + 1)};
}

// The formats (of the usual ones) that store `type`, for advice: ".exr, .tif".
std::string holders(std::string_view type) {
  std::string out;
  for (const OutputFormat& f : output_formats())
    if (f.available && f.refused.empty() && f.holds(type) &&
        (f.name == "openexr" || f.name == "tiff" || f.name == "png" || f.name == "hdr"))
      out += (out.empty() ? "" : ", ") + std::string(f.extension);
  return out;
}

// An option as the caller's users write it: "--tile 2048" on the command line (prefix "--"),
// "tile=2048" / "format='uint8'" in Python (prefix ""); `value` empty: the option alone.
std::string spelled(const std::string& prefix, const std::string& key, const std::string& value,
                    bool text) {
  if (!prefix.empty()) return prefix + key + (value.empty() ? "" : " " + value);
  return key + "=" + (value.empty() ? "" : text ? "'" + value + "'" : value);
}

}  // namespace

bool OutputFormat::holds(std::string_view type) const {
  return std::find(samples.begin(), samples.end(), type) != samples.end();
}

std::string OutputFormat::compression_names() const {
  std::string out;
  for (const CompressionChoice& c : compressions) {
    out += (out.empty() ? "" : ", ") + std::string(c.name);
    if (c.max_level > 0)
      out += "[:" + std::to_string(c.min_level) + "-" + std::to_string(c.max_level) + "]";
    if (c.quality) out += "[:QUALITY]";
  }
  return out;
}

const std::vector<OutputFormat>& output_formats() {
  static const std::vector<OutputFormat> table = build();
  return table;
}

const OutputFormat* output_format_named(std::string_view name) {
  for (const OutputFormat& f : output_formats())
    if (f.name == name) return &f;
  return nullptr;
}

const OutputFormat* output_format_for(const std::string& path) {
  auto out = OIIO::ImageOutput::create(path);
  if (!out) {
    (void)OIIO::geterror();
    return nullptr;
  }
  return output_format_named(out->format_name());
}

std::string sample_type_name(OIIO::TypeDesc type) {
  if (type == OIIO::TypeUInt8) return "uint8";
  if (type == OIIO::TypeUInt16) return "uint16";
  if (type == OIIO::TypeHalf) return "half";
  if (type == OIIO::TypeFloat) return "float";
  return type.c_str();
}

const OutputFormat& check_output(const std::string& path, const OutputRequest& r,
                                 std::string_view prefix) {
  // Appended, not "'" + clip(...): GCC 12 sees a bogus overflow in operator+(const char*, &&).
  std::string where(1, '\'');
  where.append(clip(path, 200)).append("': ");
  const std::string ext = lower(std::filesystem::path(path).extension().string());
  auto writer = OIIO::ImageOutput::create(path);
  if (!writer) {
    (void)OIIO::geterror();
    throw Error(where + "OpenImageIO writes no " +
                (ext.empty() ? "file without an extension" : "'" + clip(ext) + "' file") +
                "; write .exr, .tif, .png, .jpg or .hdr");
  }
  const OutputFormat* found = output_format_named(writer->format_name());
  if (!found)
    throw Error(where + "the " + writer->format_name() +
                " format is not one spectralize knows what it stores; write .exr, .tif or .png");
  check_format(*found, r, where, std::string(prefix));
  return *found;
}

void check_format(const OutputFormat& f, const OutputRequest& r, const std::string& where,
                  const std::string& prefix) {
  const std::string name(f.label);
  if (!f.available)
    throw Error(where + "this OpenImageIO writes no " + name + " files; write .exr or .png");
  if (const std::string why = cannot_write_here(f); !why.empty())
    throw Error(where + why + "; write .exr or .png");
  if (!f.refused.empty()) throw Error(where + name + " " + std::string(f.refused));
  if (!f.holds(r.samples)) {
    std::string kept;
    for (std::string_view s : f.samples) kept += (kept.empty() ? "" : " or ") + std::string(s);
    // The nearest type it holds: half <-> float, uint16 <-> uint8.
    std::string_view nearest = f.samples.front();
    for (const auto& [want, near] : {std::pair{"half", "float"}, std::pair{"float", "half"},
                                     std::pair{"uint16", "uint8"}, std::pair{"uint8", "uint16"}})
      if (r.samples == want && f.holds(near)) nearest = near;
    const std::string others = holders(r.samples);
    throw Error(where + name + " stores " + kept + " samples, not " + r.samples + ": use " +
                spelled(prefix, "format", std::string(nearest), true) +
                (others.empty() ? "" : ", or write " + others + " for " + r.samples));
  }
  if (r.channels > 4 && f.name != "openexr")
    throw Error(where + name + " holds RGB or RGBA, not " + std::to_string(r.channels) +
                " channels; spectral images are OpenEXR (.exr)");
  if (r.alpha && !f.alpha)
    throw Error(where + name +
                " has no alpha channel and the image has one: write .png, .tif or .exr to keep "
                "it");
  if (f.name == "hdr" && r.channels != 3)
    throw Error(where + name + " holds exactly three channels (RGB); write .exr");
  // The format's own default is always what it does (Radiance HDR: rle, whatever is asked).
  if (!r.compression.empty() && r.compression != f.default_compression) {
    // Not a structured binding: clang 14 (the fuzzers') cannot capture one in a lambda.
    const auto parts = split(r.compression);
    const std::string &cname = parts.first, &level = parts.second;
    const auto c = std::find_if(f.compressions.begin(), f.compressions.end(),
                                [&](const CompressionChoice& x) { return x.name == cname; });
    if (c == f.compressions.end())
      throw Error(where + spelled(prefix, "compression", clip(r.compression), true) + ": " + name +
                  (f.compressions.empty()
                       ? " has no compression to choose (it writes " +
                             std::string(f.default_compression) + "); leave out " +
                             spelled(prefix, "compression", "", true)
                       : " takes " + f.compression_names()));
    if (!level.empty()) {
      bool ok = false;
      if (c->quality) {
        double q = 0;
        const auto res = std::from_chars(level.data(), level.data() + level.size(), q);
        ok = res.ec == std::errc() && res.ptr == level.data() + level.size() && q > 0 &&
             std::isfinite(q);
      } else if (c->max_level > 0) {
        int v = 0;
        const auto res = std::from_chars(level.data(), level.data() + level.size(), v);
        ok = res.ec == std::errc() && res.ptr == level.data() + level.size() && v >= c->min_level &&
             v <= c->max_level;
      }
      if (!ok)
        throw Error(where + spelled(prefix, "compression", clip(r.compression), true) + ": " +
                    name + " takes " + f.compression_names());
    }
  }
  if (r.tile_width > 0) {
    if (!f.tiles)
      throw Error(where + name + " files are not tiled (tiles: .exr, .tif); leave out " +
                  spelled(prefix, "tile", "", false));
    if (r.tile_width % f.tile_multiple || r.tile_height % f.tile_multiple)
      throw Error(where + name + " tiles are multiples of " + std::to_string(f.tile_multiple) +
                  " pixels, not " + std::to_string(r.tile_width) + "x" +
                  std::to_string(r.tile_height));
    const std::int64_t sample = r.samples == "half" || r.samples == "uint16" ? 2
                                : r.samples == "uint8"                       ? 1
                                                                             : 4;
    const std::int64_t bytes =
        static_cast<std::int64_t>(r.tile_width) * r.tile_height * r.channels * sample;
    if (f.max_tile_bytes > 0 && bytes > f.max_tile_bytes) {
      // The largest power-of-two square tile that fits.
      int side = 16;
      while (static_cast<std::int64_t>(side) * 2 * side * 2 * r.channels * sample <=
             f.max_tile_bytes)
        side *= 2;
      throw Error(where + "a tile of " + std::to_string(r.tile_width) + "x" +
                  std::to_string(r.tile_height) + " pixels of " + std::to_string(r.channels) + " " +
                  r.samples + " channels takes " + std::to_string(bytes >> 20) + " MB, and " +
                  name + " holds at most 2 GB per tile: use " +
                  spelled(prefix, "tile", std::to_string(side), false) + " or less");
    }
  }
}

void apply_compression(OIIO::ImageSpec& spec, const OutputFormat& f,
                       const std::string& compression) {
  spec.erase_attribute("compression");
  const std::string text = compression.empty() ? std::string(f.default_compression) : compression;
  const auto [name, level] = split(text);
  if (f.name == "png") {
    // OIIO 2.4's PNG writer ignores "compression": the deflate level is png:compressionLevel.
    spec.attribute("png:compressionLevel", level.empty() ? 6 : std::stoi(level));
  } else if (f.name == "tiff") {
    spec.attribute("compression", name);
    if (name == "zip") spec.attribute("tiff:zipquality", level.empty() ? 6 : std::stoi(level));
  } else if (!f.compressions.empty()) {
    spec.attribute("compression", text);  // OpenEXR, JPEG, WebP, HEIF, Targa: NAME[:LEVEL]
  }
}

std::string cannot_write_here(const OutputFormat& format) {
  // HEIF's encoders are libheif plugins, which a system may lack (Debian 13 and later ship them
  // in packages of their own): OIIO then lists the format and fails at the first image.
  if (format.name != "heif" || !format.available) return "";
  static const std::string why = [&] {
    const std::string failure =
        probe_write(std::string(format.name), std::string(format.extension));
    return failure.empty() ? failure
                           : "OpenImageIO's HEIF writer cannot encode here (" + clip(failure, 200) +
                                 "): libheif has no HEVC or AV1 encoder (Debian: "
                                 "libheif-plugin-x265 or libheif-plugin-aomenc)";
  }();
  return why;
}

std::string compression_help() {
  std::string exr, others;
  for (const OutputFormat& f : output_formats()) {
    if (!f.available || !f.refused.empty() || f.compressions.empty()) continue;
    if (f.name == "openexr")
      exr = f.compression_names();
    else
      others += (others.empty() ? "" : "; ") + std::string(f.label) + " " + f.compression_names();
  }
  return "OpenEXR " + exr + " (plain zip is zip:4, dwaa dwaa:45); --to-rgb also " + others;
}

std::vector<std::string_view> all_compression_names() {
  // Only formats this OpenImageIO writes: a name no output can take is not offered.
  static const std::vector<std::string_view> names = [] {
    std::vector<std::string_view> out;
    for (const OutputFormat& f : output_formats())
      if (f.available && f.refused.empty())
        for (const CompressionChoice& c : f.compressions)
          if (std::find(out.begin(), out.end(), c.name) == out.end()) out.push_back(c.name);
    return out;
  }();
  return names;
}

bool compression_level_range(std::string_view name, int& min_level, int& max_level) {
  bool any = false;
  for (const OutputFormat& f : output_formats()) {
    if (!f.available || !f.refused.empty()) continue;
    for (const CompressionChoice& c : f.compressions)
      if (c.name == name && c.max_level > 0) {
        min_level = any ? std::min(min_level, c.min_level) : c.min_level;
        max_level = any ? std::max(max_level, c.max_level) : c.max_level;
        any = true;
      }
  }
  return any;
}

}  // namespace spectralize
