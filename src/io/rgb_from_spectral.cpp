#include "io/rgb_from_spectral.h"

#include <algorithm>
#include <cmath>

#include "core/colorimetry.h"
#include "core/error.h"
#include "core/spectralizer.h"
#include "io/spectral_layout.h"

namespace spectralize {

SpectralLayoutInfo analyse_spectral_layout(const OIIO::ImageSpec& spec, const std::string& file) {
  SpectralLayoutInfo info;
  std::vector<std::pair<double, int>> s0, t;
  bool stokes_other = false;
  for (int c = 0; c < spec.nchannels; ++c) {
    const std::string name(spec.channel_name(c));
    if (name == "A") info.alpha = c;
    auto parsed = parse_spectral_channel(name);
    if (!parsed) continue;
    if (parsed->kind == SpectralChannel::Kind::reflective)
      t.emplace_back(parsed->wavelength_nm, c);
    else if (parsed->stokes == 0)
      s0.emplace_back(parsed->wavelength_nm, c);
    else
      stokes_other = true;
  }
  const std::string where = "'" + file + "': ";
  if (s0.empty() && t.empty())
    throw Error(where + (stokes_other ? "has S1..S3 channels but no S0 (intensity) channels"
                                      : "has no spectral channels (S0.<wavelength>nm or "
                                        "T.<wavelength>nm)"));
  if (!s0.empty() && !t.empty())
    throw Error(where + "has both emissive (S0) and reflective (T) channels");
  auto& bands = s0.empty() ? t : s0;
  info.emissive = !s0.empty();
  info.polarised = stokes_other;
  // Channels may come in any order (EXR sorts names as text: "1000,0nm" before "950,0nm").
  std::sort(bands.begin(), bands.end());
  for (std::size_t i = 1; i < bands.size(); ++i)
    if (bands[i].first == bands[i - 1].first)
      throw Error(where + "channels '" + std::string(spec.channel_name(bands[i - 1].second)) +
                  "' and '" + std::string(spec.channel_name(bands[i].second)) +
                  "' are the same wavelength");
  if (bands.size() < 2) throw Error(where + "has a single spectral band; a spectrum needs two");
  for (const auto& [nm, c] : bands) {
    info.wavelengths.push_back(nm);
    info.band_channels.push_back(c);
  }
  return info;
}

RgbFromSpectral::RgbFromSpectral(const SpectralLayoutInfo& layout, const RgbSettings& settings,
                                 const ColourSpaces& spaces)
    : layout_(layout), from_xyz_(spaces.from_xyz(settings.colorspace)) {
  const Observer& observer = Observer::get(settings.observer);
  std::unique_ptr<Illuminant> illuminant;
  if (!layout.emissive)
    illuminant = std::make_unique<Illuminant>(Illuminant::get(settings.illuminant));
  SampleWeights w(layout.wavelengths, observer, illuminant.get());
  for (const Xyz& c : w.columns()) {
    wx_.push_back(static_cast<float>(c.X));
    wy_.push_back(static_cast<float>(c.Y));
    wz_.push_back(static_cast<float>(c.Z));
  }
  if (!layout.emissive) {
    const Xyz white = w.unit_white();
    balance_[0] = static_cast<float>(kWhiteD65.X / white.X);
    balance_[1] = static_cast<float>(kWhiteD65.Y / white.Y);
    balance_[2] = static_cast<float>(kWhiteD65.Z / white.Z);
  }
}

void RgbFromSpectral::convert(const float* in, int in_nch, std::size_t n, float* out) const {
  const int out_nch = output_channels();
  const std::size_t bands = layout_.band_channels.size();
  for (std::size_t p = 0; p < n; ++p) {
    const float* px = in + p * in_nch;
    float X = 0, Y = 0, Z = 0;
    for (std::size_t i = 0; i < bands; ++i) {
      const float v = px[layout_.band_channels[i]];
      X += wx_[i] * v;
      Y += wy_[i] * v;
      Z += wz_[i] * v;
    }
    float* o = out + p * out_nch;
    o[0] = X * balance_[0];
    o[1] = Y * balance_[1];
    o[2] = Z * balance_[2];
    if (out_nch == 4) o[3] = px[layout_.alpha];
  }
  // OCIO works on packed RGB: convert the triples in place when there is no alpha, else via
  // a small buffer.
  if (out_nch == 3) {
    from_xyz_.apply(out, n);
  } else {
    std::vector<float> rgb(n * 3);
    for (std::size_t p = 0; p < n; ++p)
      for (int c = 0; c < 3; ++c) rgb[p * 3 + c] = out[p * 4 + c];
    from_xyz_.apply(rgb.data(), n);
    for (std::size_t p = 0; p < n; ++p)
      for (int c = 0; c < 3; ++c) out[p * 4 + c] = rgb[p * 3 + c];
  }
}

}  // namespace spectralize
