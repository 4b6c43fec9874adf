#include "path_tracer/sigmoid_texture.h"

#include <algorithm>

namespace spectralize::path_tracer {

SigmoidTexture::SigmoidTexture(const baseline::SigmoidTable& table, std::vector<float> rgb)
    : table_(table), rgb_(std::move(rgb)) {}

void SigmoidTexture::eval(std::uint32_t texel, std::span<const WavelengthPacket> packets,
                          float* out) const {
  const float* c = &rgb_[3 * static_cast<std::size_t>(texel)];
  const auto unit = [](float v) { return std::clamp(v, 0.0f, 1.0f); };
  const baseline::SigmoidPolynomial p = table_(unit(c[0]), unit(c[1]), unit(c[2]));
  for (const WavelengthPacket& w : packets) {
    p.eval4(w.nm.data(), out);
    out += kLanes;
  }
}

}  // namespace spectralize::path_tracer
