#include "spectralize/core/colorimetry.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <mutex>
#include <optional>

#include "core/colorimetry/embedded_data.h"
#include "core/decimal_number.h"
#include "spectralize/core/error.h"

namespace spectralize {

namespace {

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

std::string join(const std::vector<std::string>& v) {
  std::string out;
  for (const auto& s : v) out += (out.empty() ? "" : ", ") + s;
  return out;
}

std::vector<std::string_view> split(std::string_view line, char sep) {
  std::vector<std::string_view> out;
  std::size_t pos = 0;
  while (true) {
    std::size_t next = line.find(sep, pos);
    out.push_back(line.substr(pos, next == line.npos ? line.npos : next - pos));
    if (next == line.npos) break;
    pos = next + 1;
  }
  return out;
}

std::string_view file_text(std::string_view file) {
  for (const auto& f : embedded::data_files())
    if (f.name == file) return f.text;
  throw Error("embedded data: no table '" + std::string(file) + "'");
}

// Splits CSV text into trimmed lines, dropping empty ones and carriage returns.
std::vector<std::string_view> lines_of(std::string_view text) {
  std::vector<std::string_view> lines;
  for (auto line : split(text, '\n')) {
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.remove_suffix(1);
    if (!line.empty()) lines.push_back(line);
  }
  return lines;
}

double parse_double(std::string_view s) {
  double v = 0;
  auto r = std::from_chars(s.data(), s.data() + s.size(), v);
  if (r.ec != std::errc()) throw Error("embedded data: bad number '" + std::string(s) + "'");
  return v;
}

// Linear interpolation of (x, y) at xq, holding the end values outside [x0, xn].
double interpolate(const std::vector<double>& x, const std::vector<double>& y, double xq) {
  if (xq <= x.front()) return y.front();
  if (xq >= x.back()) return y.back();
  auto it = std::upper_bound(x.begin(), x.end(), xq);
  std::size_t i = static_cast<std::size_t>(it - x.begin());
  double t = (xq - x[i - 1]) / (x[i] - x[i - 1]);
  return y[i - 1] + t * (y[i] - y[i - 1]);
}

std::vector<double> on_reference(const std::vector<double>& x, const std::vector<double>& y) {
  std::vector<double> out(ReferenceTable::kSize);
  for (std::size_t k = 0; k < out.size(); ++k)
    out[k] = interpolate(x, y, ReferenceTable::wavelength(k));
  return out;
}

Observer load_observer(std::string name, std::string_view file) {
  Observer o;
  o.name = std::move(name);
  const char* cols[3] = {"xbar", "ybar", "zbar"};
  for (int c = 0; c < 3; ++c) {
    auto [x, y] = embedded_column(file, cols[c]);
    // The CMF tables are already on 360..830 at 1 nm: check rather than resample silently.
    if (x.size() != ReferenceTable::kSize || x.front() != ReferenceTable::kStartNm)
      throw Error("embedded data: " + std::string(file) + " is not 360..830 nm at 1 nm");
    o.cmf[c] = std::move(y);
  }
  for (std::size_t k = 0; k < ReferenceTable::kSize; ++k)
    o.y_integral += ReferenceTable::trapezoid(k) * o.cmf[1][k];
  return o;
}

// The CIE 1931 observer as Mitsuba 3 integrates it: the table's 5 nm points, linear between
// them (95 samples, 360..830 nm), and the constant its film divides by (MI_CIE_Y_NORMALIZATION
// = 1 / 106.7502593994140625, 0.1% less than the integral of that ybar, 106.857: a unit
// spectrum renders as Y = 1.001). A light's spectrum meets Mitsuba's film only with both.
constexpr double kMitsubaYIntegral = 106.7502593994140625;
Observer at_5nm(const Observer& o, std::string name) {
  Observer out;
  out.name = std::move(name);
  for (int c = 0; c < 3; ++c) {
    out.cmf[c].resize(ReferenceTable::kSize);
    for (std::size_t k = 0; k < ReferenceTable::kSize; ++k) {
      const std::size_t a = k - k % 5, b = std::min(a + 5, ReferenceTable::kSize - 1);
      const double t = b == a ? 0.0 : static_cast<double>(k - a) / static_cast<double>(b - a);
      out.cmf[c][k] = (1 - t) * o.cmf[c][a] + t * o.cmf[c][b];
    }
  }
  out.y_integral = kMitsubaYIntegral;
  return out;
}

// CIE 015 daylight series at correlated colour temperature `cct` (K) from S0, S1, S2.
std::vector<double> daylight(double cct) {
  double t = cct * 1.4388 / 1.4380;  // the 1968 change of c2 (CIE 015:2018 note)
  double xd = (t <= 7000) ? -4.6070e9 / (t * t * t) + 2.9678e6 / (t * t) + 0.09911e3 / t + 0.244063
                          : -2.0064e9 / (t * t * t) + 1.9018e6 / (t * t) + 0.24748e3 / t + 0.237040;
  double yd = -3.000 * xd * xd + 2.870 * xd - 0.275;
  double m = 0.0241 + 0.2562 * xd - 0.7341 * yd;
  double m1 = (-1.3515 - 1.7703 * xd + 5.9114 * yd) / m;
  double m2 = (0.0300 - 31.4424 * xd + 30.0717 * yd) / m;
  const std::string_view file = "cie_daylight_basis_s0_s1_s2_5nm.csv";
  auto s0 = embedded_column_on_reference(file, "S0");
  auto s1 = embedded_column_on_reference(file, "S1");
  auto s2 = embedded_column_on_reference(file, "S2");
  std::vector<double> out(ReferenceTable::kSize);
  for (std::size_t k = 0; k < out.size(); ++k) out[k] = s0[k] + m1 * s1[k] + m2 * s2[k];
  return out;
}

const std::string_view kFluorescentFile = "cie_illuminants_fl_hp_led_5nm.csv";

// A Planckian (blackbody) radiator at `kelvin` on the reference table, Planck's law with CIE
// 015:2018's c2 = 1.4388e-2 m K (ITS-90; section 3.1, the value illuminant A is defined
// with), relative: 100 at 560 nm as CIE tables are (docs/DESIGN.md §3).
std::vector<double> planckian(double kelvin) {
  constexpr double c2 = 1.4388e-2;
  auto m = [&](double nm) {
    const double l = nm * 1e-9;
    return 1.0 / (std::pow(l, 5) * std::expm1(c2 / (l * kelvin)));
  };
  const double at560 = m(560.0);
  std::vector<double> out(ReferenceTable::kSize);
  for (std::size_t k = 0; k < out.size(); ++k)
    out[k] = 100.0 * m(ReferenceTable::wavelength(k)) / at560;
  return out;
}

// The shortest decimal text that reads back as `v` ("3200", "2856.5").
std::string decimal_text(double v) {
  char buf[32];
  const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v);
  return ec == std::errc{} ? std::string(buf, end) : std::to_string(v);
}

// "3200K", "2856.5k": the temperature of a Planckian radiator's name; none when `n` is no such
// name.
std::optional<double> kelvin_of(std::string_view n) {
  if (n.size() < 2 || (n.back() != 'k' && n.back() != 'K')) return std::nullopt;
  const std::string_view digits = n.substr(0, n.size() - 1);
  if (!std::isdigit(static_cast<unsigned char>(digits.front()))) return std::nullopt;
  try {
    return decimal_number(digits);
  } catch (const Error&) {
    return std::nullopt;
  }
}

}  // namespace

std::vector<std::string> embedded_columns(std::string_view file) {
  auto lines = lines_of(file_text(file));
  std::vector<std::string> out;
  auto header = split(lines.at(0), ',');
  for (std::size_t i = 1; i < header.size(); ++i) out.emplace_back(header[i]);
  return out;
}

std::pair<std::vector<double>, std::vector<double>> embedded_column(std::string_view file,
                                                                    std::string_view column) {
  auto lines = lines_of(file_text(file));
  auto header = split(lines.at(0), ',');
  auto it = std::find(header.begin(), header.end(), column);
  if (it == header.end() || it == header.begin())
    throw Error("embedded data: " + std::string(file) + " has no column '" + std::string(column) +
                "'");
  std::size_t col = static_cast<std::size_t>(it - header.begin());
  std::vector<double> x, y;
  for (std::size_t i = 1; i < lines.size(); ++i) {
    auto cells = split(lines[i], ',');
    if (cells.size() != header.size())
      throw Error("embedded data: " + std::string(file) + " row " + std::to_string(i) +
                  " has the wrong number of cells");
    x.push_back(parse_double(cells[0]));
    y.push_back(cells[col].empty() ? 0.0 : parse_double(cells[col]));
  }
  return {std::move(x), std::move(y)};
}

EmbeddedTable embedded_table(std::string_view file) {
  const auto lines = lines_of(file_text(file));
  const auto header = split(lines.at(0), ',');
  EmbeddedTable t;
  for (std::size_t c = 1; c < header.size(); ++c) t.names.emplace_back(header[c]);
  t.columns.resize(t.names.size());
  for (std::size_t i = 1; i < lines.size(); ++i) {
    const auto cells = split(lines[i], ',');
    if (cells.size() != header.size())
      throw Error("embedded data: " + std::string(file) + " row " + std::to_string(i) +
                  " has the wrong number of cells");
    t.wavelengths.push_back(parse_double(cells[0]));
    for (std::size_t c = 1; c < cells.size(); ++c)
      t.columns[c - 1].push_back(cells[c].empty() ? 0.0 : parse_double(cells[c]));
  }
  return t;
}

std::vector<double> embedded_column_on_reference(std::string_view file, std::string_view column) {
  auto [x, y] = embedded_column(file, column);
  return on_reference(x, y);
}

const Observer& Observer::get(std::string_view name) {
  static std::once_flag once;
  static std::optional<Observer> cie1931, cie1931_mitsuba, cie1964;
  std::call_once(once, [] {
    cie1931 = load_observer("cie1931", "cie1931_2deg_cmf_1nm.csv");
    cie1931_mitsuba = at_5nm(*cie1931, "cie1931_mitsuba");
    cie1964 = load_observer("cie1964", "cie1964_10deg_cmf_1nm.csv");
  });
  std::string n = lower(name);
  if (n == "cie1931" || n == "cie1931_2" || n == "1931" || n == "2") return *cie1931;
  if (n == "cie1931_mitsuba") return *cie1931_mitsuba;
  if (n == "cie1964" || n == "cie1964_10" || n == "1964" || n == "10") return *cie1964;
  throw Error("unknown observer " + quote(name) + " (valid: " + join(names()) + ")");
}

std::vector<std::string> Observer::names() {
  return {"cie1931", "cie1931_mitsuba", "cie1964"};
}

Illuminant Illuminant::get(std::string_view name) {
  std::string n = lower(name);
  // "F11" is how the paper and most tools name CIE FL11 (F1..F12).
  if (n.size() >= 2 && n.size() <= 3 && n[0] == 'f' &&
      std::all_of(n.begin() + 1, n.end(), [](char c) { return std::isdigit(c); }))
    n = "fl" + n.substr(1);
  Illuminant il;
  if (n == "d65") {
    il = {"D65", embedded_column_on_reference("cie_illuminant_d65_1nm.csv", "value")};
  } else if (n == "d50") {
    il = {"D50", embedded_column_on_reference("cie_illuminant_d50_1nm.csv", "value")};
  } else if (n == "a") {
    il = {"A", embedded_column_on_reference("cie_illuminant_a_1nm.csv", "value")};
  } else if (n == "c") {
    il = {"C", embedded_column_on_reference("cie_illuminant_c_5nm.csv", "value")};
  } else if (n == "e") {
    il = {"E", std::vector<double>(ReferenceTable::kSize, 100.0)};
  } else if (const auto kelvin = kelvin_of(n)) {
    if (!(*kelvin >= kMinPlanckianKelvin && *kelvin <= kMaxPlanckianKelvin))
      throw Error("illuminant " + quote(name) + ": a Planckian radiator is made for " +
                  decimal_text(kMinPlanckianKelvin) + ".." + decimal_text(kMaxPlanckianKelvin) +
                  " K");
    il = {decimal_text(*kelvin) + "K", planckian(*kelvin)};
  } else if (n.size() >= 3 && n.size() <= 4 && n[0] == 'd' &&
             std::all_of(n.begin() + 1, n.end(), [](char c) { return std::isdigit(c); })) {
    int hundreds = std::stoi(n.substr(1));
    if (hundreds < 40 || hundreds > 250)
      throw Error("illuminant " + quote(name) +
                  ": daylight series is defined for D40..D250 (4000..25000 K)");
    il = {std::string("D").append(n, 1, std::string::npos), daylight(hundreds * 100.0)};
  } else {
    for (const auto& col : embedded_columns(kFluorescentFile)) {
      if (lower(col) == n) {
        il = {col, embedded_column_on_reference(kFluorescentFile, col)};
        break;
      }
    }
    if (il.name.empty())
      throw Error("unknown illuminant " + quote(name) + " (valid: " + join(names()) + ")");
  }
  return il;
}

std::vector<std::string> Illuminant::names() {
  std::vector<std::string> out = {"D65",
                                  "D50",
                                  "A",
                                  "C",
                                  "E",
                                  "D<nn> (D40..D250, e.g. D55, D75)",
                                  "<T>K (a Planckian radiator, 1000..25000 K, e.g. 3200K)"};
  for (const auto& col : embedded_columns(kFluorescentFile)) out.push_back(col);
  return out;
}

}  // namespace spectralize
