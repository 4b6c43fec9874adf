#include "path_tracer/rt_texture.h"

namespace spectralize::path_tracer {

RtTexture::RtTexture(const spz_table* table, std::vector<float> rgb, float scale)
    : table_(table), rgb_(std::move(rgb)), scale_(scale) {}

void RtTexture::eval(std::uint32_t texel, std::span<const WavelengthPacket> packets,
                     float* out) const {
  spz_spectrum s;
  const int status = spz_fetch(table_, &rgb_[3 * static_cast<std::size_t>(texel)], &s);
  // Mapped colours still get an exact spectrum (of the mapped colour); invalid ones the zero
  // spectrum. Both are counted for the report, not fixed up here.
  if (status == 1) mapped_.fetch_add(1, std::memory_order_relaxed);
  if (status < 0) invalid_.fetch_add(1, std::memory_order_relaxed);
  for (const WavelengthPacket& p : packets) {
    spz_eval4(&s, p.nm.data(), out);
    for (int i = 0; i < kLanes; ++i) out[i] *= scale_;
    out += kLanes;
  }
}

}  // namespace spectralize::path_tracer
