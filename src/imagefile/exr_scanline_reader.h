#pragma once
// Scanline OpenEXR inputs read by OpenEXR itself with a bounded number of decoded chunks
// (docs/DESIGN.md §10). OpenEXR decodes whole chunks (1 row for none/rle/zips, 16 for zip/pxr24,
// 32 for piz/b44/dwaa, 256 for dwab) and keeps max(1, 2 x threads) of them; through OIIO that is
// twice the process's OpenEXR threads, so a DWAB map of 8192 float RGB rows held 4 x 25 MB on two
// cores and would hold 64 x 25 MB on 32. Here the thread count is chosen from the chunk's size,
// so memory does not depend on how the input is stored or on the number of cores.

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace spectralize {

class ExrScanlineReader {
 public:
  /// A reader of the scanline OpenEXR `path` whose first part has every channel of `names`
  /// (half or float, sampling 1), or nullptr when it is anything else (tiled, deep, subsampled,
  /// integer channels: those are read through OIIO). Decoded chunks kept: at most `budget`
  /// bytes (at least one chunk), decoded by up to `workers` threads. Never throws (nullptr).
  /// Cost: reading the header.
  static std::unique_ptr<ExrScanlineReader> open(const std::string& path,
                                                 const std::vector<std::string>& names,
                                                 std::size_t budget, int workers);
  ~ExrScanlineReader();

  /// Rows [y0, y1) of the data window (0 = its top), every channel of `names` in that order,
  /// as float, into `out` (width x channels per row). Throws Error naming the file. Cost:
  /// decoding the chunks that hold them (a chunk read by the previous call is not decoded
  /// again).
  void read(int y0, int y1, float* out);
  /// Rows per chunk, and the decoded chunks OpenEXR keeps. Cost: O(1).
  int chunk_rows() const;
  int chunks_kept() const;

 private:
  struct Impl;
  explicit ExrScanlineReader(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace spectralize
