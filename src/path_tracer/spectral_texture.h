#pragma once
// What a path tracer asks of a texture: a texel's spectrum at the wavelengths its paths carry.
// The renderer's spectra come through this interface from spectralize::rt (rt_texture.h), from
// the Jakob & Hanika baseline (sigmoid_texture.h) or from sampled spectra (sampled_spectra.h:
// the dense reference and the measured truth), so one path sampler renders them all alike.

#include <cstddef>
#include <cstdint>
#include <span>

#include "path_tracer/wavelengths.h"

namespace spectralize::path_tracer {

/// The spectra of a texture's texels: reflectances of a surface or radiances of a light.
class SpectralTexture {
 public:
  virtual ~SpectralTexture() = default;
  /// Number of texels. Cost: O(1).
  virtual std::size_t texels() const = 0;
  /// Texel `texel`'s spectrum at the wavelengths of `packets`: kLanes floats per packet into
  /// `out`, in order. Thread-safe. Cost: O(packets) after an O(1) lookup of the texel.
  virtual void eval(std::uint32_t texel, std::span<const WavelengthPacket> packets,
                    float* out) const = 0;
};

}  // namespace spectralize::path_tracer
