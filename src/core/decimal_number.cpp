#include "core/decimal_number.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "spectralize/core/error.h"

namespace spectralize {

double decimal_number(std::string_view text) {
  const std::string quoted = quote(text);
  // std::from_chars takes no '+' (strtod does): a sign is a sign either way.
  std::string_view digits = text;
  if (!digits.empty() && digits.front() == '+') {
    digits.remove_prefix(1);
    if (!digits.empty() && (digits.front() == '+' || digits.front() == '-'))
      throw Error(quoted + " is not a number");
  }
  const std::string_view unsigned_part =
      !digits.empty() && digits.front() == '-' ? digits.substr(1) : digits;
  if (unsigned_part.size() > 1 && unsigned_part[0] == '0' &&
      (unsigned_part[1] == 'x' || unsigned_part[1] == 'X')) {
    // strtod reads C's hexadecimal floats: say what it is and its decimal value.
    const std::string t(text);
    char* end = nullptr;
    const double v = std::strtod(t.c_str(), &end);
    if (end == t.c_str() + t.size() && std::isfinite(v)) {
      char buf[40];
      std::snprintf(buf, sizeof buf, "%.17g", v);
      throw Error(quoted + " is a hexadecimal number; write it in decimal (" + buf + ")");
    }
    throw Error(quoted + " is not a number");
  }
  double v = 0;
  const auto r = std::from_chars(digits.data(), digits.data() + digits.size(), v);
  if (digits.empty() || r.ptr != digits.data() + digits.size() ||
      (r.ec != std::errc() && r.ec != std::errc::result_out_of_range))
    throw Error(quoted + " is not a number");
  if (r.ec == std::errc::result_out_of_range)
    throw Error(quoted + " is out of the range of a double (about 2.2e-308 to 1.8e308 in size)");
  if (!std::isfinite(v)) throw Error(quoted + " is not a finite number");
  return v;
}

}  // namespace spectralize
