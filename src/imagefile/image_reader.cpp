#include "imagefile/image_reader.h"

#include <algorithm>
#include <cstring>
#include <thread>

#include "core/work_counts.h"
#include "imagefile/exr_header.h"
#include "imagefile/exr_scanline_reader.h"
#include "imagefile/safe_output.h"
#include "spectralize/core/error.h"
#include "text/strings.h"

namespace spectralize {

namespace {

// What OpenEXR may keep of decoded input chunks (at least one chunk, ~2x its decoded size):
// 16 MB, e.g. two 16-row zip chunks of 8192 float RGB pixels, or one 256-row DWAB chunk of any
// width.
constexpr std::size_t kChunkBudget = 16u << 20;

// Throws when a declared size is beyond ImageLimits, naming it.
void check_declared_size(const std::string& where, long long w, long long h) {
  if (w > ImageLimits::kMaxSide || h > ImageLimits::kMaxSide || w * h > ImageLimits::kMaxPixels)
    throw Error(where + "declares " + std::to_string(w) + "x" + std::to_string(h) +
                " pixels, beyond spectralize's limit (sides up to 1048576, 2^32 pixels)");
}

}  // namespace

ImageReader::ImageReader(const std::string& path, int output_channels, bool straight_alpha)
    : path_(path) {
  // Opening may nest (a recipe's source is opened by the plugin on this thread): if that ever
  // overflows the stack, the crash handler still needs a stack to run on.
  ensure_signal_stack();
  // Refused before OIIO sees it: a FIFO or a device would block or never end.
  check_readable_file(path, "input");
  OIIO::ImageSpec config;
  // Straight alpha as stored: OIIO would otherwise multiply 8-bit encoded values by alpha
  // before the transfer function is undone (docs/DESIGN.md §9, "Alpha").
  if (straight_alpha) config.attribute("oiio:UnassociatedAlpha", 1);
  const std::string where = quoted_path(path) + ": ";
  count_work(Work::input_opened);
  in_ = OIIO::ImageInput::open(path, &config);
  if (!in_) {
    const std::string why = OIIO::geterror();
    // OIIO 3 refuses an OpenEXR header declaring more pixels than the file could hold before
    // spectralize sees its size: the same limit, in the same words, from the header itself.
    if (const auto box = exr_header_values(path).boxes; box.count("dataWindow")) {
      const auto& d = box.at("dataWindow");
      check_declared_size(where, static_cast<long long>(d[2]) - d[0] + 1,
                          static_cast<long long>(d[3]) - d[1] + 1);
    }
    throw Error(where + "cannot read: " + (why.empty() ? "unknown format" : clip(why, 300)));
  }
  spec_ = in_->spec();
  if (spec_.depth > 1) throw Error(where + "volume images are not supported");
  const long long w = spec_.width, h = spec_.height;
  if (w <= 0 || h <= 0 || spec_.nchannels <= 0)
    throw Error(where + "empty image (" + std::to_string(w) + "x" + std::to_string(h) + ", " +
                std::to_string(spec_.nchannels) + " channels)");
  check_declared_size(where, w, h);
  if (spec_.nchannels > ImageLimits::kMaxChannels)
    throw Error(where + "declares " + std::to_string(spec_.nchannels) +
                " channels, beyond the limit of 1024");
  const long long row = w * static_cast<long long>(std::max(spec_.nchannels, output_channels)) * 4;
  if (row > ImageLimits::kMaxRowBytes)
    throw Error(where + "one row of " + std::to_string(w) + " pixels would take " +
                std::to_string(row >> 20) + " MB, beyond the limit of 256 MB per row");
  straight_ = straight_alpha && spec_.alpha_channel >= 0 &&
              spec_.get_int_attribute("oiio:UnassociatedAlpha", 0) != 0;
  // MIP levels and subimages, for the report: only level 0 of subimage 0 is read.
  OIIO::ImageSpec level;
  while (in_->seek_subimage(0, mip_levels_)) ++mip_levels_;
  while (in_->seek_subimage(subimages_, 0)) ++subimages_;
  if (!in_->seek_subimage(0, 0)) throw Error(where + "cannot read: " + clip(in_->geterror(), 300));
  (void)OIIO::geterror();  // the failed seeks above leave messages behind
  (void)in_->geterror();
  format_ = in_->format_name();
  // Scanline OpenEXR: OpenEXR itself, keeping at most kChunkBudget of decoded chunks whatever
  // the compression and the cores (docs/DESIGN.md §10); OIIO's reader is closed so that its
  // own chunk buffers go too.
  if (format_ == "openexr" && spec_.tile_width == 0 && !spec_.deep) {
    const int workers = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    exr_ = ExrScanlineReader::open(path, spec_.channelnames, kChunkBudget, workers);
    if (exr_) {
      in_->close();
      in_.reset();
    }
  }
}

ImageReader::~ImageReader() {
  if (in_) in_->close();
}

std::string ImageReader::format_name() const {
  return format_;
}

int ImageReader::aligned_rows(int wanted) const {
  const int unit = std::max(1, tile_height());
  return std::max(unit, (wanted + unit - 1) / unit * unit);
}

void ImageReader::read_rows(int y0, int y1, float* out) {
  const int nch = spec_.nchannels;
  const std::size_t row_values = static_cast<std::size_t>(spec_.width) * nch;
  auto fail = [&](const std::string& why) {
    throw Error(quoted_path(path_) + ": cannot read rows " + std::to_string(y0) + ".." +
                std::to_string(y1 - 1) + ": " + clip(why, 300));
  };
  if (exr_) {
    exr_->read(y0, y1, out);
    return;
  }
  if (tile_height() == 0) {
    if (!in_->read_scanlines(0, 0, spec_.y + y0, spec_.y + y1, 0, 0, nch, OIIO::TypeFloat, out))
      fail(in_->geterror());
    return;
  }
  // Tiled: read whole rows of tiles (OIIO 2.4's read_scanlines divides by zero on tiled
  // files), keep the last block for the next call.
  const int th = tile_height();
  for (int y = y0; y < y1;) {
    if (y < tiles_y0_ || y >= tiles_y1_) {
      tiles_y0_ = y / th * th;
      tiles_y1_ = std::min(spec_.height, tiles_y0_ + th);
      tiles_.resize(row_values * static_cast<std::size_t>(tiles_y1_ - tiles_y0_));
      if (!in_->read_tiles(0, 0, spec_.x, spec_.x + spec_.width, spec_.y + tiles_y0_,
                           spec_.y + tiles_y1_, spec_.z, spec_.z + 1, 0, nch, OIIO::TypeFloat,
                           tiles_.data())) {
        tiles_y0_ = tiles_y1_ = 0;
        fail(in_->geterror());
      }
    }
    const int rows = std::min(y1, tiles_y1_) - y;
    std::memcpy(out + static_cast<std::size_t>(y - y0) * row_values,
                tiles_.data() + static_cast<std::size_t>(y - tiles_y0_) * row_values,
                static_cast<std::size_t>(rows) * row_values * sizeof(float));
    y += rows;
  }
}

}  // namespace spectralize
