#include "spectralize/core/edge_filter.h"

#include <algorithm>
#include <charconv>
#include <cmath>

#include "core/decimal_number.h"
#include "spectralize/core/error.h"

namespace spectralize {

EdgeFilter EdgeFilter::fraction(double f) {
  if (!(f >= 0 && f < 1))
    throw Error("edge filter: a fraction must be in [0, 1), got " + std::to_string(f));
  EdgeFilter e;
  e.kind_ = Kind::fraction;
  e.value_ = f;
  return e;
}

EdgeFilter EdgeFilter::count(std::size_t k) {
  EdgeFilter e;
  e.kind_ = Kind::count;
  e.value_ = static_cast<double>(k);
  return e;
}

EdgeFilter EdgeFilter::automatic() {
  EdgeFilter e;
  e.kind_ = Kind::automatic;
  e.value_ = kAutoLadder[0];
  return e;
}

EdgeFilter EdgeFilter::parse(std::string_view text) {
  const std::string quoted = "edge filter " + quote(text) + ": ";
  if (text == "none") return EdgeFilter();
  if (text == "auto") return automatic();
  bool percent = !text.empty() && text.back() == '%';
  std::string_view num = percent ? text.substr(0, text.size() - 1) : text;
  double v = 0;
  try {
    // Its own spelling only (to_string's): no sign before the number.
    if (!num.empty() && num.front() == '+') throw Error(quote(num) + " has a sign");
    v = decimal_number(num);
  } catch (const Error& e) {
    throw Error(quoted + e.what() +
                ": expected auto, a fraction (0.7), a percentage (70%), a count (1000) or none");
  }
  if (v < 0) throw Error(quoted + "must not be negative");
  if (percent) {
    if (v >= 100) throw Error(quoted + "a percentage must be below 100%");
    return fraction(v / 100.0);
  }
  bool integral = num.find_first_of(".eE") == std::string_view::npos;
  if (integral) return count(static_cast<std::size_t>(v));
  if (v >= 1) throw Error(quoted + "a fraction must be below 1 (use an integer for a count)");
  return fraction(v);
}

std::size_t EdgeFilter::drop_count(std::size_t admissible) const {
  if (admissible == 0) return 0;
  std::size_t k =
      (kind_ == Kind::count)
          ? static_cast<std::size_t>(value_)
          : static_cast<std::size_t>(std::floor(value_ * static_cast<double>(admissible)));
  return std::min(k, admissible - 1);
}

std::string EdgeFilter::to_string() const {
  if (kind_ == Kind::automatic) return "auto";
  if (kind_ == Kind::count) return std::to_string(static_cast<std::size_t>(value_));
  char buf[32];
  auto r = std::to_chars(buf, buf + sizeof buf, value_);
  std::string s(buf, r.ptr);
  return s.find('.') == std::string::npos && s.find('e') == std::string::npos ? s + ".0" : s;
}

EdgeBands::EdgeBands(std::span<const double> wavelengths) {
  if (wavelengths.empty()) return;
  const double first = wavelengths.front(), last = wavelengths.back();
  for (std::size_t i = 0; i < wavelengths.size(); ++i) {
    const double nm = wavelengths[i];
    if (nm <= first + EdgeFilter::kEdgeBandNm || nm >= last - EdgeFilter::kEdgeBandNm)
      edge_.push_back(i);
    if (nm >= 400 && nm <= 700) interior_.push_back(i);
  }
  if (interior_.empty())
    for (std::size_t i = 0; i < wavelengths.size(); ++i)
      if (std::find(edge_.begin(), edge_.end(), i) == edge_.end()) interior_.push_back(i);
}

double EdgeBands::interior_mean(std::span<const double> spectrum) const {
  double mean = 0;
  for (std::size_t i : interior_) mean += spectrum[i];
  return interior_.empty() ? 0.0 : mean / static_cast<double>(interior_.size());
}

bool EdgeBands::free_of_peaks(std::span<const double> spectrum) const {
  if (interior_.empty()) return true;
  const double mean = interior_mean(spectrum);
  for (std::size_t i : edge_)
    if (spectrum[i] > mean) return false;
  return true;
}

double EdgeBands::edge_ratio(std::span<const double> spectrum) const {
  const double mean = interior_mean(spectrum);
  double peak = 0;
  for (std::size_t i : edge_) peak = std::max(peak, spectrum[i]);
  return mean > 0 ? peak / mean : 0.0;
}

}  // namespace spectralize
