#pragma once
// RGB textures made spectral at every lookup through spectralize::rt, the way a renderer drops
// it in for pbrt-v4's RGBAlbedoSpectrum / RGBIlluminantSpectrum: spz_fetch on the texel's linear
// RGB, then spz_eval4 at the path's wavelengths. Only <spectralize/rt.h> (the C API) is used.

#include <spectralize/rt.h>

#include <atomic>
#include <vector>

#include "path_tracer/spectral_texture.h"

namespace spectralize::path_tracer {

class RtTexture final : public SpectralTexture {
 public:
  /// `rgb`: 3 linear floats per texel in the table's colour space; each spectrum is multiplied
  /// by `scale` (a light's brightness; emission spectra are scale-free). `table` must outlive
  /// this. Cost: O(1).
  RtTexture(const spz_table* table, std::vector<float> rgb, float scale = 1);

  std::size_t texels() const override { return rgb_.size() / 3; }
  /// spz_fetch of the texel's RGB, spz_eval4 per packet. Cost: one fetch + one eval4 a packet.
  void eval(std::uint32_t texel, std::span<const WavelengthPacket> packets,
            float* out) const override;
  /// Lookups so far whose colour the table had to map into its gamut first (spz_fetch == 1) or
  /// could not use (< 0). Cost: O(1).
  long mapped() const { return mapped_.load(); }
  long invalid() const { return invalid_.load(); }

 private:
  const spz_table* table_;
  std::vector<float> rgb_;
  float scale_;
  mutable std::atomic<long> mapped_{0}, invalid_{0};
};

}  // namespace spectralize::path_tracer
