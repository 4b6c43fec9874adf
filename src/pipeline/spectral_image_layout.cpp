#include "pipeline/spectral_image_layout.h"

#include "colour/colour_tags.h"
#include "imagefile/output_metadata.h"
#include "imagefile/spectral_channel.h"
#include "spectralize/version.h"

namespace spectralize {

namespace {

class SpectralExrLayout final : public SpectralImageLayout {
 public:
  explicit SpectralExrLayout(const LayoutRequest& r);
  const OIIO::ImageSpec& spec() const override { return spec_; }
  int band_channel() const override { return bands_; }
  int preview_channel() const override { return 0; }
  int alpha_channel() const override { return alpha_; }
  const std::string& preview_colorspace() const override { return preview_; }

 private:
  OIIO::ImageSpec spec_;
  int bands_ = 3, alpha_ = -1;
  std::string preview_;
};

SpectralExrLayout::SpectralExrLayout(const LayoutRequest& r) : preview_(r.preview_colorspace) {
  const Settings& s = r.settings;
  const SpectralizerSettings& sp = s.spectral;
  const OIIO::ImageSpec& in = r.input;
  alpha_ = r.alpha ? 3 : -1;
  bands_ = r.alpha ? 4 : 3;
  const int nch = bands_ + static_cast<int>(sp.grid.size());
  spec_ = OIIO::ImageSpec(in.width, in.height, nch, s.half ? OIIO::TypeHalf : OIIO::TypeFloat);
  spec_.x = in.x;
  spec_.y = in.y;
  spec_.full_x = in.full_x;
  spec_.full_y = in.full_y;
  spec_.full_width = in.full_width;
  spec_.full_height = in.full_height;
  spec_.channelnames = {"R", "G", "B"};
  // ImageSpec makes channel 3 the alpha of any image with 4 or more channels: only a real A is.
  spec_.alpha_channel = alpha_;
  if (r.alpha) spec_.channelnames.push_back("A");
  const auto kind = sp.mode == Mode::emission ? SpectralChannel::Kind::emissive
                                              : SpectralChannel::Kind::reflective;
  for (std::size_t i = 0; i < sp.grid.size(); ++i)
    spec_.channelnames.push_back(spectral_channel_name(kind, sp.grid[i]));
  for (const auto& p : in.extra_attribs)
    if (carried_over_attribute(p.name().string())) spec_.extra_attribs.push_back(p);
  spec_.attribute("compression", s.compression);
  if (s.tile_width > 0) {
    spec_.tile_width = s.tile_width;
    spec_.tile_height = s.tile_height;
  }
  spec_.attribute(kLayoutVersionAttr, kLayoutVersion);
  if (sp.mode == Mode::emission) spec_.attribute(kEmissiveUnitsAttr, kEmissiveUnits);
  spec_.attribute("Software", "spectralize " SPECTRALIZE_VERSION);
  spec_.attribute("DateTime", r.date_time);
  spec_.attribute("spectralize:version", SPECTRALIZE_VERSION);
  // The settings the file was made with, as resolved for it, from the schema (docs/DESIGN.md
  // §8): the same list ingest's up-to-date key hashes (file_settings).
  for (const auto& [setting, value] : file_settings(s))
    if (!setting->attribute.empty())
      spec_.attribute("spectralize:" + std::string(setting->attribute), value);
  for (const auto& [name, value] : r.attributes) spec_.attribute(name, value);
  for (const auto& [name, value] : r.numbers) spec_.attribute(name, OIIO::TypeDesc::DOUBLE, &value);
  tag_colour_space(spec_, r.spaces, preview_);
}

// Arrays of colours: the bands, nothing else, as floats.
class BareSpectraLayout final : public SpectralImageLayout {
 public:
  explicit BareSpectraLayout(const SpectralizerSettings& sp) {
    spec_ = OIIO::ImageSpec(1, 1, static_cast<int>(sp.grid.size()), OIIO::TypeFloat);
    spec_.alpha_channel = -1;
    const auto kind = sp.mode == Mode::emission ? SpectralChannel::Kind::emissive
                                                : SpectralChannel::Kind::reflective;
    for (std::size_t i = 0; i < sp.grid.size(); ++i)
      spec_.channelnames[i] = spectral_channel_name(kind, sp.grid[i]);
  }
  const OIIO::ImageSpec& spec() const override { return spec_; }
  int band_channel() const override { return 0; }
  int preview_channel() const override { return -1; }
  int alpha_channel() const override { return -1; }
  const std::string& preview_colorspace() const override { return none_; }

 private:
  OIIO::ImageSpec spec_;
  std::string none_;
};

}  // namespace

std::unique_ptr<SpectralImageLayout> bare_spectra_layout(const SpectralizerSettings& settings) {
  return std::make_unique<BareSpectraLayout>(settings);
}

std::unique_ptr<SpectralImageLayout> spectral_exr_layout(const LayoutRequest& request) {
  return std::make_unique<SpectralExrLayout>(request);
}

}  // namespace spectralize
