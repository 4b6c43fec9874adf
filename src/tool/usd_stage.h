#pragma once
// `spectralize ingest STAGE.usd[a|c|z]`: a USD stage's textures and lights. OpenUSD has Python
// bindings on PyPI (usd-core), none in Debian for C++: the stage is read by the Python module's
// spectralize.usd (docs/guide/usd.md), run as a helper process; its textures are ingested here
// as list lines, its lights and spectral.usda written by the helper afterwards.

#include <string>
#include <vector>

namespace spectralize::tool {

/// True for a path OpenUSD opens as a stage (.usd, .usda, .usdc, .usdz; any case). Cost: O(1).
bool is_usd_stage(const std::string& path);

/// Runs spectralize.usd's command-line half (`_main(args)`) in the Python that has OpenUSD
/// ($SPECTRALIZE_PYTHON, else the project's virtual environment, else python3) with the module
/// this build made on its path; its stdout and stderr are the caller's. Returns its exit status
/// (3: no OpenUSD there). Throws FileError when no Python can be started. Cost: a process,
/// Python's start and OpenUSD's import (about a second).
int run_usd_helper(const std::vector<std::string>& args);

/// Which Python run_usd_helper starts, for messages. Cost: O(1).
std::string usd_python();

}  // namespace spectralize::tool
