#include "imagefile/openexr_compat.h"

#include <ImfCompression.h>
#include <OpenEXRConfig.h>

namespace spectralize {

const std::vector<ExrCompression>& exr_compressions() {
  static const std::vector<ExrCompression> all = [] {
    std::vector<ExrCompression> out;
// (OPENEXR_VERSION_HEX casts: not for the preprocessor.)
#if OPENEXR_VERSION_MAJOR > 3 || (OPENEXR_VERSION_MAJOR == 3 && OPENEXR_VERSION_MINOR >= 2)
    // OpenEXR 3.2 names its compressions, their block heights and lossiness itself.
    for (int i = 0; i < Imf::NUM_COMPRESSION_METHODS; ++i) {
      const auto id = static_cast<Imf::Compression>(i);
      if (!Imf::isValidCompression(i)) continue;
      ExrCompression c;
      c.id = i;
      Imf::getCompressionNameFromId(id, c.name);
      c.block_rows = Imf::getCompressionNumScanlines(id);
      c.lossy = Imf::isLossyCompression(id);
      out.push_back(c);
    }
#else
    // OpenEXR 3.1's, in its enum's order (ImfCompression.h).
    out = {{0, "none", 1, false}, {1, "rle", 1, false},  {2, "zips", 1, false},
           {3, "zip", 16, false}, {4, "piz", 32, false}, {5, "pxr24", 16, true},
           {6, "b44", 32, true},  {7, "b44a", 32, true}, {8, "dwaa", 32, true},
           {9, "dwab", 256, true}};
#endif
    return out;
  }();
  return all;
}

std::string openexr_version() {
  return OPENEXR_VERSION_STRING;
}

}  // namespace spectralize
