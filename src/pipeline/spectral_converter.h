#pragma once
// The pixel kernel (docs/DESIGN.md §10): RGB(A) rows in, rows of a spectral image layout out.
// Colour through OCIO to XYZ, alpha by its stated rules, spectra from the exact table, samples
// rounded as the file stores them, previews integrated back from the written samples, and
// every pixel counted by kind. No decisions: the caller gives channels, transforms and layout.

#include <cstdint>
#include <memory>
#include <mutex>
#include <vector>

#include "classify/input_interpretation.h"
#include "colour/colour_space.h"
#include "core/tables/spectral_table.h"
#include "pipeline/spectral_image_layout.h"
#include "pipeline/thread_share.h"
#include "spectralize/core/spectralizer.h"

namespace spectralize {

/// What the kernel counted, summed over all calls.
struct PixelCounts {
  std::uint64_t invalid = 0;              // NaN / Inf colour: zero spectrum
  std::uint64_t negative = 0;             // negative luminance: zero spectrum (out of gamut)
  std::uint64_t outside_locus = 0;        // mapped into the spectral locus
  std::uint64_t outside_solid = 0;        // reflectance: mapped into the reflectance solid
  std::uint64_t brighter_than_white = 0;  // reflectance: Y above the reference white's (mapped)
  std::uint64_t negative_component = 0;   // some RGB component < 0 (information)
  std::uint64_t black = 0;
  std::uint64_t half_overflow = 0;  // a sample above HALF's 65504, clamped
  std::uint64_t alpha_invalid = 0;  // alpha NaN, infinite or outside [0, 1]: made finite, clamped
  std::uint64_t error_pixels = 0;   // pixels the XYZ error is measured on (non-black)
  double max_error = 0, sum_error = 0;
  /// Adds another set of counts. Cost: O(1).
  void add(const PixelCounts& o);
};

class SpectralConverter {
 public:
  struct Setup {
    const Spectralizer& spectralizer;
    SpectralTable& table;
    ChannelRoles channels;
    int input_channels = 3;
    bool straight_alpha = false;  // colour not yet multiplied by alpha (PNG, TIFF, ...)
    ColourTransform to_xyz;       // input space -> CIE XYZ (D65)
    ColourTransform to_preview;   // CIE XYZ (D65) -> the previews' space
    const SpectralImageLayout& layout;
    bool half = true;
    int threads = 0;
    const ThreadShare* share = nullptr;  // a batch's cores: its share now, instead of threads
  };

  /// Keeps the setup (the spectralizer, table and layout must outlive the converter). Cost: O(N).
  explicit SpectralConverter(Setup setup);

  /// Converts n pixels of input_channels floats into n output pixels of the layout (floats,
  /// already rounded to HALF and clamped to its range for HALF output), in parallel on OIIO's
  /// pool. Alpha: colour is premultiplied in linear light; a reflectance is the spectrum of the
  /// straight colour times alpha (docs/DESIGN.md §9). Thread-safe. Cost: O(n x bands).
  void convert(const float* in, std::size_t n, float* out);

  /// The counts so far. Cost: O(1).
  PixelCounts counts() const;

 private:
  void load_colours(const float* in, std::size_t b, std::size_t m, float* rgb, float* alpha,
                    PixelCounts& c) const;
  void finish_pixel(float* o, const PixelResult& r, float scale, float alpha, float* preview_xyz,
                    PixelCounts& c) const;

  Setup s_;
  std::size_t bands_ = 0;
  int out_nch_ = 0;
  std::vector<float> wx_, wy_, wz_;  // integration weights, to measure what is written
  float unbalance_[3] = {1, 1, 1};   // from the spectra's white back to D65, for previews
  double white_y_ = 1;               // Y of the reference white (reflectance brightness)
  mutable std::mutex mutex_;
  PixelCounts total_;
};

}  // namespace spectralize
