#pragma once
// Spectral EXRs and test images, independently of the library: OIIO to read and write the
// pixels, our own channel-name regex, and our own integration weights built from the CIE CSV
// tables.

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <regex>
#include <string>
#include <vector>

#include "cli_support.h"

namespace e2e {

struct Exr {
  int width = 0, height = 0;
  std::vector<std::string> channels;
  std::vector<float> pixels;                      // interleaved, all channels, as float
  std::map<std::string, std::string> attributes;  // string-valued attributes
  bool tiled = false;
  std::string format;  // "half" or "float" (of channel 0)
  int channel(const std::string& name) const {
    auto it = std::find(channels.begin(), channels.end(), name);
    return it == channels.end() ? -1 : static_cast<int>(it - channels.begin());
  }
  float at(int x, int y, int c) const {
    return pixels[(static_cast<std::size_t>(y) * width + x) * channels.size() + c];
  }
};

inline Exr read_exr(const std::string& path) {
  Exr e;
  auto in = OIIO::ImageInput::open(path);
  if (!in) return e;
  const OIIO::ImageSpec& spec = in->spec();
  e.width = spec.width;
  e.height = spec.height;
  e.channels = spec.channelnames;
  e.tiled = spec.tile_width > 0;
  e.format = spec.format.c_str();
  for (const auto& p : spec.extra_attribs)
    if (p.type() == OIIO::TypeString) e.attributes[p.name().string()] = p.get_string();
  e.pixels.resize(static_cast<std::size_t>(e.width) * e.height * e.channels.size());
  in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeFloat, e.pixels.data());
  return e;
}

/// The largest difference between the samples of `a` and `b` (same channel order); infinite
/// when their sizes differ.
inline double max_difference(const Exr& a, const Exr& b) {
  if (a.pixels.size() != b.pixels.size()) return INFINITY;
  double worst = 0;
  for (std::size_t i = 0; i < a.pixels.size(); ++i)
    worst = std::max(worst, static_cast<double>(std::abs(a.pixels[i] - b.pixels[i])));
  return worst;
}

/// Writes a float RGB image of w x h pixels (interleaved `rgb`).
inline void write_exr(const std::string& path, int w, int h, const std::vector<float>& rgb) {
  OIIO::ImageSpec spec(w, h, 3, OIIO::TypeDesc::FLOAT);
  auto out = OIIO::ImageOutput::create(path);
  ASSERT_TRUE(out && out->open(path, spec));
  ASSERT_TRUE(out->write_image(OIIO::TypeFloat, rgb.data()));
  out->close();
}

/// Writes an image of any channel names and sample type, every sample `value` unless `pixels`;
/// `edit` may add attributes to the spec first.
inline void write_image(const std::string& path, int w, int h,
                        const std::vector<std::string>& names, OIIO::TypeDesc type,
                        const std::vector<float>& pixels = {}, float value = 0.5f,
                        const std::function<void(OIIO::ImageSpec&)>& edit = nullptr) {
  OIIO::ImageSpec spec(w, h, static_cast<int>(names.size()), type);
  spec.channelnames = names;
  spec.alpha_channel = -1;
  for (std::size_t c = 0; c < names.size(); ++c)
    if (names[c] == "A") spec.alpha_channel = static_cast<int>(c);
  if (edit) edit(spec);
  std::vector<float> px = pixels;
  if (px.empty()) px.assign(static_cast<std::size_t>(w) * h * names.size(), value);
  auto out = OIIO::ImageOutput::create(path);
  ASSERT_TRUE(out && out->open(path, spec)) << OIIO::geterror();
  ASSERT_TRUE(out->write_image(OIIO::TypeFloat, px.data()));
  ASSERT_TRUE(out->close());
}

/// The sample format and size of a file, without reading its pixels.
inline std::string exr_format(const std::string& path, int* width = nullptr) {
  auto in = OIIO::ImageInput::open(path);
  if (!in) return "";
  if (width) *width = in->spec().width;
  return in->spec().format.c_str();
}

/// The spectral channels of a file: (channel index, wavelength nm), sorted by wavelength.
/// Parsed with the layout's reference regex, written out here again on purpose.
inline std::vector<std::pair<int, double>> spectral_channels(const Exr& e, const char* prefix) {
  static const std::regex re(
      R"(^((S([0-3]))|T)\.(\d*,?\d*([Ee][+-]?\d+)?)(Y|Z|E|P|T|G|M|k|h|da|d|c|m|u|n|p)?(m|Hz)$)");
  std::vector<std::pair<int, double>> out;
  for (std::size_t c = 0; c < e.channels.size(); ++c) {
    std::smatch m;
    if (!std::regex_match(e.channels[c], m, re)) continue;
    if (e.channels[c].rfind(prefix, 0) != 0) continue;
    std::string num = m[4].str();
    std::replace(num.begin(), num.end(), ',', '.');
    if (m[7].str() != "m") continue;  // hertz: not written by spectralize
    const std::string unit = m[6].str();
    const double to_nm = unit == "n"    ? 1.0
                         : unit == "u"  ? 1e3
                         : unit == "p"  ? 1e-3
                         : unit.empty() ? 1e9
                                        : 0.0;
    if (to_nm == 0) continue;
    out.emplace_back(static_cast<int>(c), std::stod(num) * to_nm);
  }
  std::sort(out.begin(), out.end(), [](auto& a, auto& b) { return a.second < b.second; });
  return out;
}

/// Integration weights (X, Y, Z per band) of piecewise-linear spectra on `nm`, from the 1 nm
/// CIE tables (trapezoid); emission normalised by K, reflectance (illuminant file given) by the
/// Y of rho == 1 on the same wavelengths.
inline std::vector<std::array<double, 3>> band_weights(const std::vector<double>& nm,
                                                       const std::string& cmf_file,
                                                       const std::string& illuminant_file = "") {
  Table cmf = read_table(cmf_file, {"xbar", "ybar", "zbar"});
  Table ill;
  if (!illuminant_file.empty()) ill = read_table(illuminant_file, {"value"});
  std::vector<std::array<double, 3>> w(nm.size(), {0, 0, 0});
  double norm = 0, white_y = 0;
  for (std::size_t k = 0; k < cmf.nm.size(); ++k) {
    const double l = cmf.nm[k];
    const double tau = (k == 0 || k + 1 == cmf.nm.size()) ? 0.5 : 1.0;
    double e = 1;
    if (!illuminant_file.empty())
      for (std::size_t j = 0; j < ill.nm.size(); ++j)
        if (ill.nm[j] == l) e = ill.cols[0][j];
    norm += tau * cmf.cols[1][k];
    if (l < nm.front() || l > nm.back()) continue;
    for (std::size_t i = 0; i + 1 < nm.size(); ++i) {
      if (l < nm[i] || l > nm[i + 1]) continue;
      const double t = (l - nm[i]) / (nm[i + 1] - nm[i]);
      for (int c = 0; c < 3; ++c) {
        w[i][c] += tau * e * (1 - t) * cmf.cols[c][k];
        w[i + 1][c] += tau * e * t * cmf.cols[c][k];
      }
      break;
    }
  }
  for (const auto& b : w) white_y += b[1];
  const double divide = illuminant_file.empty() ? norm : white_y;
  for (auto& b : w)
    for (double& v : b) v /= divide;
  return w;
}

}  // namespace e2e
