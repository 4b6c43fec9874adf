#pragma once
// What each output format can hold (docs/DESIGN.md §9): sample types, tiles and their limits,
// compression names and levels, the slot for the colour space, alpha and channel counts. One
// table, consulted by every writer (spectral OpenEXR, --to-rgb, plots and figures) before any
// work, so that a file is never quietly something else than asked (uint16 written as uint8,
// half as float, an ignored --compression) and a refusal names the format and what to use
// instead. Built from OpenImageIO's own answers where it gives them (which formats this build
// writes, ImageOutput::supports: tiles, alpha, I/O proxies, and whether a writer whose codec
// is a plugin can write here) and from stated facts about OIIO 2.4's and 3.1's writers where
// it does not (the sample types each stores, compression names); the unit test checks every
// stated fact against files OIIO writes and reads back.

#include <OpenImageIO/imageio.h>

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace spectralize {

/// A compression a format's writer takes: a name, optionally with a level (NAME:LEVEL), a whole
/// number from min to max when max > 0, any number above 0 when `quality` (OpenEXR's DWA).
struct CompressionChoice {
  std::string_view name{};
  int min_level = 0, max_level = 0;
  bool quality = false;
  bool lossy = false;
};

/// Where a format says which colour space its RGB is in.
enum class ColourSlot {
  attributes,     // OpenEXR: oiio:ColorSpace, colorInteropID, chromaticities
  icc_profile,    // TIFF, PNG, JPEG: an ICC profile
  linear_rec709,  // Radiance HDR, PFM: none; readers assume linear Rec.709
  srgb,           // none; readers assume sRGB
};

struct OutputFormat {
  std::string_view name{};                  // OIIO's format name ("openexr")
  std::string_view label{};                 // for people: "OpenEXR"
  std::string_view extension{};             // the usual one, for advice: ".exr"
  std::vector<std::string_view> samples{};  // of uint8, uint16, half, float: stored exactly so
  std::vector<CompressionChoice> compressions{};  // empty: the writer has no choice
  std::string_view default_compression{};         // what the writer does when nothing is asked
  ColourSlot colour = ColourSlot::srgb;
  bool alpha = false;               // keeps a fourth channel as alpha (OIIO's supports("alpha"))
  bool tiles = false;               // writes real tiles (supports("tiles"), not emulated)
  int tile_multiple = 1;            // tile sides must be multiples of this (TIFF: 16)
  std::int64_t max_tile_bytes = 0;  // one tile's uncompressed bytes at most (0: no limit)
  bool proxy = false;               // OIIO's writer writes correctly through an IOProxy
  bool available = false;           // this OIIO build writes it
  std::string_view refused{};       // non-empty: not written by spectralize, and why

  /// True when the format stores samples of `type` ("uint8", "uint16", "half", "float") as
  /// given. Cost: O(types).
  bool holds(std::string_view type) const;
  /// The compression choices as people write them: "zip[:1-9], piz, ...". Cost: O(choices).
  std::string compression_names() const;
};

/// Every format of the table, in the order of advice (OpenEXR, TIFF, PNG first). Cost: a few
/// OIIO queries the first time, O(1) after.
const std::vector<OutputFormat>& output_formats();

/// The format OIIO writes for `path` (by its extension; ".pfm" is the PFM entry), or nullptr
/// when OIIO writes no such file or the table does not know the format. Cost: O(formats).
const OutputFormat* output_format_for(const std::string& path);

/// The table's entry for an OIIO format name ("openexr", "png"), or nullptr. Cost: O(formats).
const OutputFormat* output_format_named(std::string_view name);

/// The sample type name of an OIIO type ("uint8", "uint16", "half", "float"; else its own).
/// Cost: O(1).
std::string sample_type_name(OIIO::TypeDesc type);

/// What a writer is about to ask of a file.
struct OutputRequest {
  std::string samples;                  // "uint8", "uint16", "half" or "float"
  std::string compression;              // "" : the format's default
  int tile_width = 0, tile_height = 0;  // 0: scanlines
  int channels = 3;                     // 3 (RGB), 4 (RGBA) or more (spectral OpenEXR)
  bool alpha = false;                   // the last channel is alpha
};

/// Checks `request` against the format of `path` before any work: a format OIIO writes and the
/// table does not refuse, the sample type, the compression (name and level), tiles (the
/// format's, their multiple, the byte limit), alpha and the channel count. Throws Error
/// "'<path>': <FORMAT> ...; <what to use instead>", options spelled for `prefix`'s users
/// ("--" for the CLI: "--format uint8"; "" for Python: "format='uint8'"). Returns the format. Cost:
/// O(table). (`prefix` is a view: a temporary string there would make the returned reference,
/// to the static table, look dangling to GCC 13+'s -Wdangling-reference.)
const OutputFormat& check_output(const std::string& path, const OutputRequest& request,
                                 std::string_view prefix = "--");

/// check_output for a known format, the messages starting with `where` ("'x.exr': ").
/// Cost: O(table).
void check_format(const OutputFormat& format, const OutputRequest& request,
                  const std::string& where, const std::string& prefix = "--");

/// Sets on `spec` the attributes through which `format`'s writer takes `compression` (already
/// checked; "" for the default): OpenEXR's and TIFF's "compression", PNG's
/// png:compressionLevel, JPEG's "jpeg:QUALITY", ...; none for formats without a choice.
/// Cost: O(1).
void apply_compression(OIIO::ImageSpec& spec, const OutputFormat& format,
                       const std::string& compression);

/// Why this build cannot write `format` files after all, or "": OIIO lists HEIF, whose
/// encoders are libheif plugins a system may lack; probed once, writing a 2 x 2 image, on the
/// first need. Cost: that write once per process for HEIF, O(1) otherwise.
std::string cannot_write_here(const OutputFormat& format);

/// The compressions of every format this build writes, for --help: "OpenEXR none, rle, zips[:1-
/// 9], ... (plain zip is zip:4, dwaa dwaa:45); --to-rgb also TIFF none, lzw, ...". Cost: the
/// format table.
std::string compression_help();

/// Every compression name a format this OpenImageIO writes takes, and the level range of `name`
/// across those formats (for the settings schema's first check of --compression). Cost:
/// O(table) (the table is made once per process).
std::vector<std::string_view> all_compression_names();
bool compression_level_range(std::string_view name, int& min_level, int& max_level);

}  // namespace spectralize
