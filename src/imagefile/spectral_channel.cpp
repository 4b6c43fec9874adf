#include "imagefile/spectral_channel.h"

#include <charconv>
#include <cmath>
#include <regex>

#include <fmt/core.h>

namespace spectralize {

std::string spectral_channel_name(SpectralChannel::Kind kind, double wavelength_nm, int stokes) {
  char buf[64];
  auto r = std::to_chars(buf, buf + sizeof buf, wavelength_nm, std::chars_format::fixed, 6);
  std::string value(buf, r.ptr);
  for (char& c : value)
    if (c == '.') c = ',';
  // std::format-free and locale-free: "S0" or "T", then the number with its comma.
  if (kind == SpectralChannel::Kind::reflective) return fmt::format("T.{}nm", value);
  return fmt::format("S{}.{}nm", stokes, value);
}

std::optional<SpectralChannel> parse_spectral_channel(std::string_view name) {
  static const std::regex pattern(
      R"(^((S([0-3]))|T)\.(\d*,?\d*([Ee][+-]?\d+)?)(Y|Z|E|P|T|G|M|k|h|da|d|c|m|u|n|p)?(m|Hz)$)");
  std::cmatch m;
  if (!std::regex_match(name.data(), name.data() + name.size(), m, pattern)) return std::nullopt;
  std::string number = m[4].str();
  for (char& c : number)
    if (c == ',') c = '.';
  if (number.empty() || number == ".") return std::nullopt;
  if (number.front() == '.') number.insert(number.begin(), '0');
  double value = 0;
  auto r = std::from_chars(number.data(), number.data() + number.size(), value);
  if (r.ec != std::errc() || r.ptr != number.data() + number.size() || !std::isfinite(value))
    return std::nullopt;
  // SI prefix, then the unit: metres (to nm by an exact power of ten, so "550,0nm" is exactly
  // 550), or hertz (to nm through the speed of light).
  static const std::pair<const char*, double> to_nm[] = {
      {"Y", 1e33}, {"Z", 1e30}, {"E", 1e27}, {"P", 1e24},  {"T", 1e21}, {"G", 1e18},
      {"M", 1e15}, {"k", 1e12}, {"h", 1e11}, {"da", 1e10}, {"", 1e9},   {"d", 1e8},
      {"c", 1e7},  {"m", 1e6},  {"u", 1e3},  {"n", 1.0},   {"p", 1e-3}};
  double factor = 0;
  const std::string prefix = m[6].matched ? m[6].str() : std::string();
  for (const auto& [p, f] : to_nm)
    if (prefix == p) factor = f;
  double nm = 0;
  if (m[7].str() == "m") {
    nm = value * factor;
  } else {
    const double hertz = value * factor * 1e-9;  // factor is relative to nano
    nm = 299792458.0 / hertz * 1e9;
  }
  if (!(nm > 0) || !std::isfinite(nm)) return std::nullopt;
  SpectralChannel c;
  c.kind = m[2].matched ? SpectralChannel::Kind::emissive : SpectralChannel::Kind::reflective;
  c.stokes = m[2].matched ? m[3].str()[0] - '0' : 0;
  c.wavelength_nm = nm;
  return c;
}

}  // namespace spectralize
