#pragma once
// RGB textures made spectral at every lookup by the comparison baseline, Jakob & Hanika 2019
// (src/baseline/sigmoid_spectrum.h), as pbrt-v4's RGBAlbedoSpectrum does: the RGB clamped to
// [0, 1], the table's trilinear fetch of three coefficients, the sigmoid at the wavelengths.

#include <vector>

#include "baseline/sigmoid_spectrum.h"
#include "path_tracer/spectral_texture.h"

namespace spectralize::path_tracer {

class SigmoidTexture final : public SpectralTexture {
 public:
  /// `rgb`: 3 linear floats per texel in the table's colour space. `table` must outlive this.
  /// Cost: O(1).
  SigmoidTexture(const baseline::SigmoidTable& table, std::vector<float> rgb);

  std::size_t texels() const override { return rgb_.size() / 3; }
  /// The table's fetch of the clamped RGB, SigmoidPolynomial::eval4 per packet. Cost: one fetch
  /// + one eval4 a packet.
  void eval(std::uint32_t texel, std::span<const WavelengthPacket> packets,
            float* out) const override;

 private:
  const baseline::SigmoidTable& table_;
  std::vector<float> rgb_;
};

}  // namespace spectralize::path_tracer
