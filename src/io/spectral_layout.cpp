#include "io/spectral_layout.h"

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
  // SI prefix, then the unit: metres, or hertz (converted through the speed of light).
  static const std::pair<const char*, double> prefixes[] = {
      {"Y", 1e24}, {"Z", 1e21}, {"E", 1e18}, {"P", 1e15}, {"T", 1e12}, {"G", 1e9},
      {"M", 1e6},  {"k", 1e3},  {"h", 1e2},  {"da", 1e1}, {"d", 1e-1}, {"c", 1e-2},
      {"m", 1e-3}, {"u", 1e-6}, {"n", 1e-9}, {"p", 1e-12}};
  double scale = 1;
  for (const auto& [p, f] : prefixes)
    if (m[6].matched && m[6].str() == p) scale = f;
  double si = value * scale;
  double nm = m[7].str() == "Hz" ? 299792458.0 / si * 1e9 : si * 1e9;
  if (!(nm > 0) || !std::isfinite(nm)) return std::nullopt;
  SpectralChannel c;
  c.kind = m[2].matched ? SpectralChannel::Kind::emissive : SpectralChannel::Kind::reflective;
  c.stokes = m[2].matched ? m[3].str()[0] - '0' : 0;
  c.wavelength_nm = nm;
  return c;
}

}  // namespace spectralize
