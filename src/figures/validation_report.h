#pragma once
// The validation's outputs: a JSON document (every number) and a Markdown report (summary
// tables, then one table per configuration), from validate()'s results.

#include <string>
#include <vector>

#include "figures/validation.h"

namespace spectralize::figures {

/// The JSON text of the results, with the definitions of every column. Cost: O(results).
std::string validation_json(const Validation& results);

/// The Markdown report. Cost: O(results).
std::string validation_markdown(const Validation& results);

/// The reflectance summary as a Markdown table, a row per configuration and space, then the
/// RGB renderer's rows (also printed by run_validation and quoted in the guide).
/// Cost: O(results).
std::string summary_table(const Validation& results);

/// The lights summary as a Markdown table. Cost: O(results).
std::string lights_table(const std::vector<ConfigResult>& results);

}  // namespace spectralize::figures
