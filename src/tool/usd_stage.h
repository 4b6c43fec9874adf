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

/// spectralize.usd's command-line half (`_main`) for one stage, in the Python that has OpenUSD
/// ($SPECTRALIZE_PYTHON, else the project's virtual environment, else python3) with the module
/// this build made on its path; its stdout and stderr are the caller's. One process serves the
/// stage: start() has it write the stage's list, finish() its layer (Python and OpenUSD start
/// once). A helper not finished is told to stop and waited for when destroyed.
class UsdStageHelper {
 public:
  UsdStageHelper() = default;
  ~UsdStageHelper();
  UsdStageHelper(const UsdStageHelper&) = delete;
  UsdStageHelper& operator=(const UsdStageHelper&) = delete;

  /// Starts `_main(["serve", args...])` and waits until the stage's list is written: 0 when
  /// it is, else the helper's exit status (1: it said why; 3: no OpenUSD). Throws FileError
  /// when no Python can be started. Cost: a process, Python's start and OpenUSD's import
  /// (about a second), composing the stage.
  int start(const std::vector<std::string>& args);

  /// Has the started helper write the stage's layer from the manifest `manifest`; its exit
  /// status (0, or 1: it said why). Cost: composing the stage's layer.
  int finish(const std::string& manifest);

 private:
  int wait();
  int pid_ = 0;
  int commands_ = -1;  // the write end of the helper's command pipe
};

/// Which Python UsdStageHelper starts, for messages. Cost: O(1).
std::string usd_python();

}  // namespace spectralize::tool
