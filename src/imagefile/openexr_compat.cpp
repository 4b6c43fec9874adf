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
      Imf::getCompressionNameFromId(id, c.name);
      c.block_rows = Imf::getCompressionNumScanlines(id);
      c.lossy = Imf::isLossyCompression(id);
      out.push_back(c);
    }
#else
    // OpenEXR 3.1's, in its enum's order (ImfCompression.h).
    out = {{"none", 1, false}, {"rle", 1, false},   {"zips", 1, false}, {"zip", 16, false},
           {"piz", 32, false}, {"pxr24", 16, true}, {"b44", 32, true},  {"b44a", 32, true},
           {"dwaa", 32, true}, {"dwab", 256, true}};
#endif
    return out;
  }();
  return all;
}

std::string openexr_version() {
  return OPENEXR_VERSION_STRING;
}

}  // namespace spectralize
