#pragma once
// Reading an input image row by row, whatever its organisation (docs/DESIGN.md §9): scanline,
// tiled, or MIP-mapped (level 0 is the image; the others are ignored and reported), checked
// before any allocation: a regular file, declared sizes within documented limits.

#include <OpenImageIO/imageio.h>

#include <memory>
#include <string>
#include <vector>

namespace spectralize {

class ExrScanlineReader;

/// The largest image spectralize opens: width or height, pixels, channels. Larger declared
/// sizes are refused at open, before anything is allocated for them.
struct ImageLimits {
  static constexpr long long kMaxSide = 1 << 20;          // 1,048,576 pixels
  static constexpr long long kMaxPixels = 1ll << 32;      // 4.3 G pixels (e.g. 64K x 64K)
  static constexpr int kMaxChannels = 1024;               // OIIO's own default limit
  static constexpr long long kMaxRowBytes = 256ll << 20;  // one row of float samples, in or out
};

class ImageReader {
 public:
  /// Opens `path` (subimage 0, MIP level 0) after checking it is a regular file, and checks its
  /// declared size against ImageLimits, also for `output_channels` float samples per pixel.
  /// `straight_alpha`: ask for unassociated (straight) alpha where the format stores it so
  /// (PNG, TIFF, ...), reported by straight_alpha(). Throws Error naming the file.
  /// Cost: reading the header.
  ImageReader(const std::string& path, int output_channels, bool straight_alpha = false);
  ~ImageReader();

  /// Level 0 of subimage 0. Cost: O(1).
  const OIIO::ImageSpec& spec() const { return spec_; }
  /// OIIO's name of the format, e.g. "openexr". Cost: O(1).
  std::string format_name() const;
  /// MIP levels and subimages in the file (1 for a plain image). Cost: O(1).
  int mip_levels() const { return mip_levels_; }
  int subimages() const { return subimages_; }
  /// Tile height, or 0 for scanline files. Cost: O(1).
  int tile_height() const { return spec_.tile_width > 0 ? spec_.tile_height : 0; }
  /// True when the colour channels are straight (not multiplied by alpha). Cost: O(1).
  bool straight_alpha() const { return straight_; }

  /// Reads rows [y0, y1) (0-based within the data window), all channels, as float, into `out`
  /// (width x channels per row). Tiled files are read in whole rows of tiles, kept until the
  /// next call needs other rows; memory is O(width x tile height). Throws Error naming the
  /// file and the rows. Cost: O(rows x width x channels).
  void read_rows(int y0, int y1, float* out);

  /// A strip height that reads efficiently: a multiple of the tile height (1 for scanlines),
  /// at least `wanted` rows when possible. Cost: O(1).
  int aligned_rows(int wanted) const;

 private:
  std::string path_, format_;
  std::unique_ptr<OIIO::ImageInput> in_;
  // Scanline OpenEXR: read by OpenEXR with a bounded number of decoded chunks (in_ closed).
  std::unique_ptr<ExrScanlineReader> exr_;
  OIIO::ImageSpec spec_;
  int mip_levels_ = 1, subimages_ = 1;
  bool straight_ = false;
  // Tiled files: the last row of tiles read (rows [tiles_y0_, tiles_y1_)).
  std::vector<float> tiles_;
  int tiles_y0_ = 0, tiles_y1_ = 0;
};

}  // namespace spectralize
