#include "path_tracer/sampled_spectra.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>

#include "pipeline/rgb_from_spectral.h"
#include "spectralize/core/error.h"

namespace spectralize::path_tracer {

SampledSpectra::SampledSpectra(float start_nm, float step_nm, std::size_t bands,
                               std::vector<float> spectra,
                               std::vector<std::uint32_t> texel_spectrum,
                               std::vector<float> texel_scale)
    : start_(start_nm),
      step_(step_nm),
      inv_step_(1 / step_nm),
      bands_(bands),
      spectra_(std::move(spectra)),
      texel_spectrum_(std::move(texel_spectrum)),
      texel_scale_(std::move(texel_scale)) {
  if (bands_ < 2 || !(step_ > 0) || spectra_.size() % bands_ != 0)
    throw Error("sampled spectra: need >= 2 bands, a step > 0 and whole spectra (got " +
                std::to_string(bands_) + " bands, " + std::to_string(spectra_.size()) +
                " samples)");
  const std::size_t count = spectra_.size() / bands_;
  for (const std::uint32_t s : texel_spectrum_)
    if (s >= count)
      throw Error("sampled spectra: texel spectrum " + std::to_string(s) + " of " +
                  std::to_string(count));
  if (!texel_scale_.empty() && texel_scale_.size() != texel_spectrum_.size())
    throw Error("sampled spectra: " + std::to_string(texel_scale_.size()) + " scales for " +
                std::to_string(texel_spectrum_.size()) + " texels");
}

SampledSpectra SampledSpectra::read_exr(const std::string& path, float scale) {
  auto in = OIIO::ImageInput::open(path);
  if (!in) throw Error("cannot read '" + path + "': " + OIIO::geterror());
  const OIIO::ImageSpec spec = in->spec();
  const SpectralLayoutInfo layout = analyse_spectral_layout(spec, path);
  const std::vector<double>& nm = layout.wavelengths;
  const double step = nm[1] - nm[0];
  for (std::size_t i = 1; i < nm.size(); ++i)
    if (std::abs(nm[i] - nm[0] - static_cast<double>(i) * step) > 1e-6)
      throw Error("'" + path + "': the bands are not evenly spaced (" + std::to_string(nm[i]) +
                  " nm)");
  const std::size_t pixels = static_cast<std::size_t>(spec.width) * spec.height;
  std::vector<float> all(pixels * spec.nchannels);
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, all.data()))
    throw Error("cannot read '" + path + "': " + in->geterror());
  const std::size_t bands = nm.size();
  std::vector<float> spectra(pixels * bands);
  std::vector<std::uint32_t> index(pixels);
  for (std::size_t p = 0; p < pixels; ++p) {
    for (std::size_t b = 0; b < bands; ++b)
      spectra[p * bands + b] = all[p * spec.nchannels + layout.band_channels[b]];
    index[p] = static_cast<std::uint32_t>(p);
  }
  SampledSpectra out(static_cast<float>(nm[0]), static_cast<float>(step), bands, std::move(spectra),
                     std::move(index),
                     scale == 1 ? std::vector<float>{} : std::vector<float>(pixels, scale));
  out.emissive_ = layout.emissive;
  return out;
}

void SampledSpectra::eval(std::uint32_t texel, std::span<const WavelengthPacket> packets,
                          float* out) const {
  const float* s = spectra_.data() + static_cast<std::size_t>(texel_spectrum_[texel]) * bands_;
  const float scale = texel_scale_.empty() ? 1.0f : texel_scale_[texel];
  const float last = static_cast<float>(bands_ - 1);
  for (const WavelengthPacket& p : packets)
    for (int i = 0; i < kLanes; ++i) {
      const float x = (p.nm[i] - start_) * inv_step_;
      float v = 0;
      if (x >= 0 && x <= last) {
        const std::size_t k = std::min(static_cast<std::size_t>(x), bands_ - 2);
        const float f = x - static_cast<float>(k);
        v = scale * (s[k] + f * (s[k + 1] - s[k]));
      }
      *out++ = v;
    }
}

}  // namespace spectralize::path_tracer
