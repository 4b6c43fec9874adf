#include "classify/light_or_surface.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "classify/input_interpretation.h"
#include "imagefile/image_reader.h"

namespace spectralize {

namespace {

constexpr const char* kLatLongWithinWhite =
    "a 2:1 map (a lat-long environment?) whose values stay within white: taken as a surface; "
    "name it *_hdri or *_env, put it in an hdri/ or env/ folder, or give --mode emission if it "
    "is a light";

}  // namespace

ModeDecision decide_mode(const ModeClues& c) {
  ModeDecision d;
  if (c.asked != ModeChoice::automatic) {
    d.mode = c.asked == ModeChoice::emission ? Mode::emission : Mode::reflectance;
    d.reason = c.asked_by.empty() ? "--mode" : c.asked_by;
    return d;
  }
  // The name (or folder) says what the map is.
  if (c.name.kind == MapKind::emission || c.name.kind == MapKind::reflectance) {
    d.mode = c.name.kind == MapKind::emission ? Mode::emission : Mode::reflectance;
    d.reason = c.name.reason;
    return d;
  }
  // RGB that spectralize made from spectra records their kind: known, so not read again (a
  // chain of recipes would otherwise decode every level below twice).
  if (c.recorded_mode == "reflectance" || c.recorded_mode == "emission") {
    d.mode = c.recorded_mode == "emission" ? Mode::emission : Mode::reflectance;
    d.reason =
        "auto: the file records that its RGB was made from " +
        std::string(d.mode == Mode::emission ? "light (emission)" : "surface (reflectance)") +
        " spectra (spectralize:mode)";
    return d;
  }
  const bool latlong = c.height > 0 && c.width == 2 * c.height;
  // 8- and 16-bit samples hold 0..1; decoded by a display or texture encoding they stay within
  // white, which no light needs to be and every surface is.
  if (!c.can_exceed_white) {
    d.mode = Mode::reflectance;
    d.reason =
        "auto: integer data in '" + c.colorspace + "' cannot exceed white: a surface (reflectance)";
    return d;
  }
  const Brightest b = c.brightest ? c.brightest() : Brightest{};
  const std::string data = c.float_data ? "floating-point data" : "integer data";
  if (b.y > kLightAboveY) {
    d.mode = Mode::emission;
    d.reason = fmt::format("auto: {} brighter than white (Y {:.4g} at row {}{}): light (emission)",
                           data, b.y, b.row, latlong ? ", a 2:1 lat-long map" : "");
    if (b.complete && b.y <= kClearlyLightY && !latlong)
      d.warnings.push_back(fmt::format(
          "its brightest pixel is barely above white (Y {:.4g}): taken as light; a texture with "
          "overshoot would be --mode reflectance",
          b.y));
    return d;
  }
  d.mode = Mode::reflectance;
  d.reason =
      fmt::format("auto: {} within white (peak Y {:.4g}): a surface (reflectance)", data, b.y);
  if (latlong && c.float_data) d.warnings.emplace_back(kLatLongWithinWhite);
  return d;
}

Brightest brightest_pixel(const std::string& file, const ChannelRoles& channels,
                          const ColourTransform& to_xyz, double stop_above_y) {
  ImageReader reader(file, 0);
  const OIIO::ImageSpec& spec = reader.spec();
  const std::size_t width = static_cast<std::size_t>(spec.width);
  const int nch = spec.nchannels;
  // About 8 MB of float samples per strip, in whole rows of tiles.
  const int wanted = static_cast<int>(
      std::clamp<std::size_t>((8u << 20) / std::max<std::size_t>(1, width * nch * 4), 1, 4096));
  const int rows = std::max(1, reader.aligned_rows(wanted));
  std::vector<float> buf(width * static_cast<std::size_t>(rows) * nch);
  std::vector<float> rgb(width * static_cast<std::size_t>(rows) * 3);
  Brightest out;
  for (int y0 = 0; y0 < spec.height; y0 += rows) {
    const int y1 = std::min(spec.height, y0 + rows);
    reader.read_rows(y0, y1, buf.data());
    const std::size_t n = width * static_cast<std::size_t>(y1 - y0);
    for (std::size_t p = 0; p < n; ++p)
      for (int k = 0; k < 3; ++k) {
        const float v = buf[p * nch + channels.colour[channels.grey() ? 0 : k]];
        rgb[p * 3 + k] = std::isfinite(v) ? v : 0.0f;
      }
    // Y alone: the middle row of the transform applied to each pixel.
    to_xyz.apply(rgb.data(), n);
    for (std::size_t p = 0; p < n; ++p) {
      const double y = rgb[p * 3 + 1];
      if (std::isfinite(y) && (out.row < 0 || y > out.y)) {
        out.y = y;
        out.row = y0 + static_cast<int>(p / width);
      }
    }
    if (out.y > stop_above_y) return out;
  }
  out.complete = true;
  return out;
}

}  // namespace spectralize
