#pragma once
// Keyword options of the Python functions, read through the settings schema (settings/settings.h):
// the CLI's options by their recipe keys, with the CLI's validation and messages.

#include <pybind11/pybind11.h>

#include <string>
#include <vector>

#include "settings/settings.h"

namespace spectralize::python {

/// What a Python function takes: the options of a command, less those that make no sense
/// there (e.g. file compression for arrays), plus its own keys read separately.
struct OptionScope {
  std::string function;               // "spectra", for messages: "spectra(): ..."
  unsigned commands = 0;              // Command bits whose settings it takes
  std::vector<std::string> excluded;  // schema keys it does not take
  std::vector<std::string> extra;     // schema keys it takes beyond `commands`
  /// True when the setting is one of this function's options. Cost: O(keys).
  bool takes(const SettingSpec& spec) const;
};

/// Reads `options` into settings: each key must be an option of `scope` (else ValueError
/// naming the valid ones), each value a str, int, float or path (else TypeError), None meaning
/// the default; values are validated by the schema (ValueError with its message). Returns the
/// settings and the keys given. Cost: O(options x settings).
Settings read_options(const pybind11::kwargs& options, const OptionScope& scope,
                      std::vector<std::string>* given = nullptr);

/// The options of `scope` for a docstring: "key: help (default: ...)" lines. Cost: O(settings).
std::string options_doc(const OptionScope& scope);

/// Raises ValueError "function(): message". Never returns.
[[noreturn]] void value_error(const OptionScope& scope, const std::string& message);

}  // namespace spectralize::python
