#pragma once
// Scanline OpenEXR written by OpenEXR itself, several whole compression blocks per call, so that
// OpenEXR compresses them in parallel on every worker (docs/DESIGN.md §10). OpenImageIO's own
// writer hands OpenEXR at most 16 MB of scanlines per call, which for a wide spectral image is
// a single block or less: one core compresses, the others wait. The header is OpenImageIO's
// (its translation of every attribute of the spec), so the file is the one it would write.

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <memory>
#include <string>

namespace spectralize {

/// The rows of one compression block of an OpenEXR compression named as OIIO names it ("zip",
/// "zip:4", "piz", "dwaa:45", ...), as OpenEXR states them: 1 (none, rle, zips), 16 (zip,
/// pxr24), 32 (piz, b44, b44a, dwaa, htj2k32) or 256 (dwab, htj2k256); 1 for a name it does not
/// know. Cost: O(compressions).
int exr_block_rows(const std::string& compression);

class ExrScanlineWriter {
 public:
  /// Opens a scanline OpenEXR of `spec` (all channels one sample type, HALF or FLOAT; its
  /// "compression" as OIIO spells it, with zip's level) on `proxy`, which receives every byte.
  /// `workers`: OpenEXR's compression threads (≥ 1; none for an image of one block). Throws
  /// Error naming `file`. Cost: OIIO writing a one-row file in memory to make the header,
  /// ~0.5 ms for 84 channels.
  ExrScanlineWriter(const OIIO::ImageSpec& spec, OIIO::Filesystem::IOProxy* proxy,
                    const std::string& file, int workers);
  ~ExrScanlineWriter();

  /// Writes rows [y, y + rows) of the data window (in order, after the previous ones) from
  /// `data`: interleaved channels in the spec's sample type. Throws Error naming the file.
  /// Cost: compressing the rows, in parallel over whole blocks.
  void write(int y, int rows, const void* data);
  /// Completes the file (its line offset table). Throws Error naming the file. Cost: O(blocks).
  void close();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace spectralize
