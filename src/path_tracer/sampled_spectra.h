#pragma once
// Textures of spectra given by their samples: the piecewise-linear function through samples on a
// uniform grid, zero outside it (docs/DESIGN.md §3), times a per-texel scale. Holds the dense
// reference (the spectral EXRs spectralize writes for a texture and an environment map), the
// measured truth (the ColorChecker's reflectances per patch) and a light of one spectrum whose
// brightness varies over a map.

#include <cstdint>
#include <string>
#include <vector>

#include "path_tracer/spectral_texture.h"

namespace spectralize::path_tracer {

class SampledSpectra final : public SpectralTexture {
 public:
  /// `spectra`: `bands` samples per spectrum at start_nm + i * step_nm; texel t is spectrum
  /// texel_spectrum[t] times texel_scale[t] (empty: 1). Throws Error for inconsistent sizes, an
  /// index out of range, fewer than two bands or a step <= 0. Cost: O(texels).
  SampledSpectra(float start_nm, float step_nm, std::size_t bands, std::vector<float> spectra,
                 std::vector<std::uint32_t> texel_spectrum, std::vector<float> texel_scale = {});

  /// A spectral OpenEXR of the layout of docs/DESIGN.md §7 (emissive S0 or reflective T
  /// channels on a uniform grid), one spectrum per pixel, row-major from the top, each times
  /// `scale`. Throws Error naming the file and the reason (unreadable, not spectral, an uneven
  /// grid). Cost: reading the file.
  static SampledSpectra read_exr(const std::string& path, float scale = 1);

  std::size_t texels() const override { return texel_spectrum_.size(); }
  void eval(std::uint32_t texel, std::span<const WavelengthPacket> packets,
            float* out) const override;
  /// Samples per spectrum. Cost: O(1).
  std::size_t bands() const { return bands_; }
  /// True for emissive (S0) files, false for reflective (T) ones and for spectra given as
  /// arrays. Cost: O(1).
  bool emissive() const { return emissive_; }

 private:
  float start_, step_, inv_step_;
  std::size_t bands_;
  std::vector<float> spectra_;
  std::vector<std::uint32_t> texel_spectrum_;
  std::vector<float> texel_scale_;
  bool emissive_ = false;
};

}  // namespace spectralize::path_tracer
