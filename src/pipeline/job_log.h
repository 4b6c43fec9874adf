#pragma once
// How the io layer's jobs talk to people: progress and messages go through callbacks, so the
// CLI, the plugin and the Python module each show them in their own way.

#include <cstdint>
#include <functional>
#include <string>

namespace spectralize {

/// Progress: pixels (or files) done of the total.
using ProgressFn = std::function<void(std::uint64_t done, std::uint64_t total)>;
/// Messages for people: level 0 a warning, 1 information, 2 detail.
using LogFn = std::function<void(int level, const std::string& message)>;

}  // namespace spectralize
