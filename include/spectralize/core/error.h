#pragma once
// The core library's one error model: configuration mistakes (bad grid, unknown observer or
// illuminant, malformed filter) throw spectralize::Error; per-colour problems (out of gamut,
// NaN, negative luminance) never throw and are reported in SpectrumResult::status instead.

#include <stdexcept>
#include <string>
#include <string_view>

namespace spectralize {

class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& what) : std::runtime_error(what) {}
};

/// An Error caused by the OCIO config itself (a missing role, colour space or XYZ route), not
/// by a value on the command line: option wrappers pass it on without naming an option.
class ConfigError : public Error {
 public:
  using Error::Error;
};

/// An Error of the file system: a file that cannot be read or written (the message names it and
/// carries the system's reason), or a destination refused because it would replace a file the
/// run reads or writes. A job failure, never a mistake of the command line.
class FileError : public Error {
 public:
  using Error::Error;
};

/// Runs `fn`; an Error it throws comes back as an Error prefixed "<context>: " (the option or
/// file it concerns), a FileError as a FileError so prefixed, except a ConfigError, which passes
/// unchanged (the config is at fault). Cost: that of fn.
template <class Fn>
auto with_context(std::string_view context, Fn&& fn) {
  try {
    return fn();
  } catch (const ConfigError&) {
    throw;
  } catch (const FileError& e) {
    throw FileError(std::string(context) + ": " + e.what());
  } catch (const Error& e) {
    throw Error(std::string(context) + ": " + e.what());
  }
}

/// A value given by a user, quoted for a message and shortened to `limit` characters (whole
/// UTF-8 characters), so that a megabyte of garbage is not echoed back. Cost: O(limit).
inline std::string quote(std::string_view value, std::size_t limit = 80) {
  std::string out = "'";
  if (value.size() <= limit) return out.append(value) + "'";
  std::size_t n = limit;
  while (n > 0 && (static_cast<unsigned char>(value[n]) & 0xC0) == 0x80) --n;
  return out.append(value.substr(0, n)) + "...' (" + std::to_string(value.size()) + " bytes)";
}

}  // namespace spectralize
