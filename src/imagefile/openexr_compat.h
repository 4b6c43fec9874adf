#pragma once
// Where OpenEXR 3.1 (Debian 12) and 3.2 to 3.4 (the VFX Reference Platform CY2026) differ,
// decided here once (docs/DESIGN.md §11); OpenEXR's headers stay in openexr_compat.cpp.

#include <string>
#include <vector>

namespace spectralize {

/// A compression this OpenEXR writes: its name as OpenEXR and OIIO spell it ("zip",
/// "htj2k256"), the scanlines of one block, and whether it loses information.
struct ExrCompression {
  int id = 0;  // the byte a header's "compression" attribute holds
  std::string name;
  int block_rows = 1;
  bool lossy = false;
};

/// Every compression of this OpenEXR, in its own order: from the library where it says them
/// (OpenEXR 3.2 and later: 3.4 adds the lossless HTJ2K), else OpenEXR 3.1's ten. Cost: O(1)
/// after the first call.
const std::vector<ExrCompression>& exr_compressions();

/// The OpenEXR this was built with ("3.4.16"). Cost: O(1).
std::string openexr_version();

}  // namespace spectralize
