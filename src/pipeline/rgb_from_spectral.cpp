#include "pipeline/rgb_from_spectral.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>

#include "colour/colour_tags.h"
#include "imagefile/output_metadata.h"
#include "imagefile/spectral_channel.h"
#include "settings/settings.h"
#include "spectralize/core/colorimetry.h"
#include "spectralize/core/error.h"
#include "spectralize/core/spectralizer.h"
#include "spectralize/version.h"
#include "text/strings.h"

namespace spectralize {

namespace {

// A wavelength as given (the shortest text that reads back as the same double).
std::string shortest(double v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

// At least two bands, and some inside the CIE tables (360-830 nm), or no colour can be made.
void check_band_span(std::size_t bands, double first_nm, double last_nm, const std::string& where) {
  if (bands < 2) throw Error(where + "has a single spectral band; a spectrum needs two");
  if (last_nm <= ReferenceTable::kStartNm ||
      first_nm >= ReferenceTable::kStartNm + ReferenceTable::kSize - 1)
    throw Error(where + "has no band inside 360-830 nm, where colour is defined (" +
                std::to_string(first_nm) + " to " + std::to_string(last_nm) + " nm)");
}

}  // namespace

SpectralLayoutInfo spectral_layout_of_samples(const std::vector<double>& wavelengths, bool emissive,
                                              const std::string& where) {
  SpectralLayoutInfo info;
  info.emissive = emissive;
  for (std::size_t i = 0; i < wavelengths.size(); ++i) {
    if (!std::isfinite(wavelengths[i]))
      throw Error(where + "wavelength " + std::to_string(i) + " is not finite");
    if (i > 0 && !(wavelengths[i] > wavelengths[i - 1]))
      throw Error(where + "wavelengths must increase strictly (" + shortest(wavelengths[i - 1]) +
                  " then " + shortest(wavelengths[i]) + " nm at " + std::to_string(i) + ")");
    info.band_channels.push_back(static_cast<int>(i));
  }
  if (!wavelengths.empty())
    check_band_span(wavelengths.size(), wavelengths.front(), wavelengths.back(), where);
  else
    check_band_span(0, 0, 0, where);
  info.wavelengths = wavelengths;
  return info;
}

SpectralLayoutInfo analyse_spectral_layout(const OIIO::ImageSpec& spec, const std::string& file) {
  SpectralLayoutInfo info;
  std::vector<std::pair<double, int>> s0, t;
  bool stokes_other = false;
  for (int c = 0; c < spec.nchannels; ++c) {
    const std::string name(spec.channel_name(c));
    if (name == "A") info.alpha = c;
    auto parsed = parse_spectral_channel(name);
    if (!parsed) {
      // Bispectral (fluorescent) channels, T.<in>.<out>: reading only the diagonal would change
      // colours a lot, so they are refused rather than reduced.
      const std::size_t dot = name.find('.', 2);
      if (name.rfind("T.", 0) == 0 && dot != std::string::npos &&
          parse_spectral_channel(name.substr(0, dot)) &&
          parse_spectral_channel("T." + name.substr(dot + 1)))
        throw Error("'" + clip(file, 200) + "': has bispectral (fluorescent) channels such as '" +
                    clip(name) + "'; spectralize reads emissive and reflective files only");
      if (name.rfind("S0.", 0) == 0 || name.rfind("S1.", 0) == 0 || name.rfind("S2.", 0) == 0 ||
          name.rfind("S3.", 0) == 0 || name.rfind("T.", 0) == 0)
        info.unparsed.push_back(name);
      continue;
    }
    if (parsed->kind == SpectralChannel::Kind::reflective)
      t.emplace_back(parsed->wavelength_nm, c);
    else if (parsed->stokes == 0)
      s0.emplace_back(parsed->wavelength_nm, c);
    else
      stokes_other = true;
  }
  const std::string where = quote(file, 200) + ": ";
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
  check_band_span(bands.size(), bands.front().first, bands.back().first, where);
  for (const auto& [nm, c] : bands) {
    info.wavelengths.push_back(nm);
    info.band_channels.push_back(c);
  }
  return info;
}

RgbFromSpectral::RgbFromSpectral(const SpectralLayoutInfo& layout, const Settings& settings,
                                 const ColourSpaces& spaces)
    : layout_(layout),
      from_xyz_(settings.display.empty()
                    ? spaces.from_xyz(settings.colorspace)
                    : spaces.display_from_xyz(settings.display, settings.view)) {
  const Observer& observer = Observer::get(settings.spectral.observer);
  std::unique_ptr<Illuminant> illuminant;
  if (!layout.emissive)
    illuminant = std::make_unique<Illuminant>(Illuminant::get(settings.spectral.illuminant));
  SampleWeights w(layout.wavelengths, observer, illuminant.get());
  for (const Xyz& c : w.columns()) {
    wx_.push_back(static_cast<float>(c.X));
    wy_.push_back(static_cast<float>(c.Y));
    wz_.push_back(static_cast<float>(c.Z));
  }
  // Balanced: relative to the reflected white (rho == 1 is the D65 white, RGB 1,1,1); as lit:
  // the reflected light itself (rho == 1 has the illuminant's colour, at Y = 1).
  if (!layout.emissive && !settings.as_lit) {
    const Xyz b = balance_to_d65(w.unit_white());
    balance_[0] = static_cast<float>(b.X);
    balance_[1] = static_cast<float>(b.Y);
    balance_[2] = static_cast<float>(b.Z);
  }
}

RgbCounts RgbFromSpectral::convert(const float* in, int in_nch, std::size_t n, float* out,
                                   OIIO::TypeDesc type) const {
  const bool integer =
      type.basetype == OIIO::TypeDesc::UINT8 || type.basetype == OIIO::TypeDesc::UINT16;
  // Values within half a code value of 0..1 round to the same codes as clamped ones: nothing
  // of them is lost, so only values beyond that are counted as clipped.
  const float half_code = type.basetype == OIIO::TypeDesc::UINT8 ? 0.5f / 255.0f : 0.5f / 65535.0f;
  const bool half = type.basetype == OIIO::TypeDesc::HALF;
  RgbCounts counts;
  const int out_nch = output_channels();
  const std::size_t bands = layout_.band_channels.size();
  std::vector<float> rgb(n * 3);
  std::vector<char> beyond_float(n, 0);  // pixels whose XYZ exceeds float's range
  for (std::size_t p = 0; p < n; ++p) {
    const float* px = in + p * in_nch;
    // In double: samples near float's limit must not overflow the sum itself.
    double X = 0, Y = 0, Z = 0;
    bool bad = false;
    for (std::size_t i = 0; i < bands; ++i) {
      float v = px[layout_.band_channels[i]];
      if (!std::isfinite(v)) v = 0, bad = true;
      X += static_cast<double>(wx_[i]) * v;
      Y += static_cast<double>(wy_[i]) * v;
      Z += static_cast<double>(wz_[i]) * v;
    }
    counts.invalid += bad;
    const double xyz[3] = {X * balance_[0], Y * balance_[1], Z * balance_[2]};
    for (int c = 0; c < 3; ++c) {
      const bool beyond = std::abs(xyz[c]) > std::numeric_limits<float>::max();
      beyond_float[p] = beyond_float[p] || beyond;
      rgb[p * 3 + c] = beyond ? std::copysign(std::numeric_limits<float>::max(), xyz[c])
                              : static_cast<float>(xyz[c]);
    }
  }
  from_xyz_.apply(rgb.data(), n);
  const float limit = half ? 65504.0f : std::numeric_limits<float>::max();
  for (std::size_t p = 0; p < n; ++p) {
    float* o = out + p * out_nch;
    bool over = beyond_float[p] != 0, clip = false;
    for (int c = 0; c < 3; ++c) {
      float v = rgb[p * 3 + c];
      // NaN only comes from a conversion that overflowed (inf - inf): out of range too.
      if (std::isnan(v)) v = 0, over = true;
      if (integer && !(v >= 0 && v <= 1)) {
        clip = clip || !(v >= -half_code && v <= 1 + half_code);
        v = std::clamp(v, 0.0f, 1.0f);
      } else if (std::abs(v) > limit) {
        over = true;
        v = std::clamp(v, -limit, limit);
      }
      o[c] = v;
    }
    counts.clipped += clip;
    (half ? counts.half_overflow : counts.float_overflow) += over && !integer;
    if (out_nch == 4) {
      const float a = in[p * in_nch + layout_.alpha];
      o[3] =
          std::isfinite(a) ? std::clamp(a, integer ? 0.0f : -limit, integer ? 1.0f : limit) : 0.0f;
    }
  }
  return counts;
}

OIIO::TypeDesc rgb_sample_type(const Settings& settings) {
  if (settings.integer_bits == 8) return OIIO::TypeUInt8;
  if (settings.integer_bits == 16) return OIIO::TypeUInt16;
  return settings.half ? OIIO::TypeHalf : OIIO::TypeFloat;
}

OIIO::ImageSpec rgb_output_spec(const OIIO::ImageSpec& source, const SpectralLayoutInfo& layout,
                                const Settings& settings, const ColourSpaces& spaces,
                                const std::string& date_time) {
  const int nch = layout.alpha >= 0 ? 4 : 3;
  OIIO::ImageSpec spec(source.width, source.height, nch, rgb_sample_type(settings));
  spec.x = source.x;
  spec.y = source.y;
  spec.full_x = source.full_x;
  spec.full_y = source.full_y;
  spec.full_width = source.full_width;
  spec.full_height = source.full_height;
  spec.channelnames = {"R", "G", "B"};
  if (layout.alpha >= 0) spec.channelnames.push_back("A");
  spec.alpha_channel = layout.alpha >= 0 ? 3 : -1;
  for (const auto& p : source.extra_attribs)
    if (carried_over_attribute(p.name().string())) spec.extra_attribs.push_back(p);
  spec.attribute("compression", settings.compression);
  if (settings.tile_width > 0) {
    spec.tile_width = settings.tile_width;
    spec.tile_height = settings.tile_height;
  }
  spec.attribute("Software", "spectralize " SPECTRALIZE_VERSION);
  spec.attribute("DateTime", date_time);
  spec.attribute("spectralize:version", SPECTRALIZE_VERSION);
  // The settings that shaped the RGB, in the schema's own words (docs/DESIGN.md §8); which of
  // them apply depends on the file read (the illuminant only for reflective files).
  const auto record = [&](const char* key) {
    spec.attribute("spectralize:" + std::string(key), setting_value(*find_setting(key), settings));
  };
  // What the RGB is (the kind of the spectra it was made from): read back by the light-or-surface
  // decision, so RGB made from a surface's spectra is spectralized as a surface again.
  spec.attribute("spectralize:mode", layout.emissive ? "emission" : "reflectance");
  record("observer");
  if (!layout.emissive) {
    record("illuminant");
    record("reflected");
  }
  if (const std::string space = rgb_output_space(settings, spaces); !space.empty())
    tag_colour_space(spec, spaces, space);
  if (!settings.display.empty()) {
    record("display");
    if (!settings.view.empty()) record("view");
  }
  return spec;
}

std::string rgb_output_space(const Settings& settings, const ColourSpaces& spaces) {
  return settings.display.empty() ? settings.colorspace
                                  : spaces.display_colour_space(settings.display, settings.view);
}

}  // namespace spectralize
