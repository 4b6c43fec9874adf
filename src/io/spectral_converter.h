#pragma once
// RGB rows in, spectral-layout rows out: the heart of the image job, shared by the CLI (which
// streams strips to a file) and the OpenImageIO plugin (which serves scanlines on demand).

#include <OpenImageIO/imageio.h>

#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "core/spectral_table.h"
#include "core/spectralizer.h"
#include "io/colour_space.h"
#include "io/image_job.h"

namespace spectralize {

class SpectralConverter {
 public:
  /// Chooses colour space and mode for an input of `input_spec` (as OIIO reports it), builds the
  /// spectralizer, its table (loading job.cache_dir's file) and the output spec: R, G, B preview,
  /// alpha, one channel per band, layout attributes and settings. Fills the setup fields of
  /// `report`. Throws Error. Cost: ~1 ms (gamut facets), plus loading the cache file.
  SpectralConverter(const ImageJobSettings& job, const OIIO::ImageSpec& input_spec,
                    const std::string& input_format, const LogFn& log, ImageReport& report);

  ~SpectralConverter();

  /// The spectral image's spec (size, channels, HALF/FLOAT, attributes). Cost: O(1).
  const OIIO::ImageSpec& output_spec() const { return out_spec_; }
  /// Channels per input pixel (as read, float) and per output pixel. Cost: O(1).
  int input_channels() const { return in_nch_; }
  int output_channels() const { return out_nch_; }

  /// Converts n pixels (input channels, float) to output pixels (float, rounded to HALF and
  /// clamped to its range when the output is HALF), in parallel on OIIO's pool, counting pixel
  /// kinds and measuring each written spectrum's XYZ error. Thread-safe. Cost: O(n x bands).
  void convert(const float* in, std::size_t n, float* out);

  /// Writes counters, errors and cache statistics into `report`, and saves the node cache if it
  /// grew. Cost: O(nodes) when saving.
  void finish(ImageReport& report, const LogFn& log);

 private:
  struct Counters;
  const ImageJobSettings& job_;
  OIIO::ImageSpec out_spec_;
  int in_nch_ = 0, out_nch_ = 0, alpha_ = -1, preview_ = 3;
  bool grey_ = false;
  std::size_t bands_ = 0;
  std::unique_ptr<ColourTransform> to_xyz_, to_preview_;
  std::unique_ptr<Spectralizer> spectralizer_;
  std::unique_ptr<SpectralTable> table_;
  std::vector<float> wx_, wy_, wz_;  // integration weights, to measure what is written
  float unbalance_[3] = {1, 1, 1};   // reflectance: back from W_ref to D65 for the preview
  std::string cache_file_;
  std::mutex mutex_;
  std::unique_ptr<Counters> total_;
};

}  // namespace spectralize
