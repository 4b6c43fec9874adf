#include "imagefile/oiio_compat.h"

#include <OpenImageIO/imagebufalgo.h>

namespace spectralize {

OIIO::ImageBuf box_resize(const OIIO::ImageBuf& src, OIIO::ROI roi) {
#if OIIO_VERSION >= OIIO_MAKE_VERSION(3, 0, 0)
  // OIIO 3 deprecates the filter-name overload for the one taking keyword arguments.
  return OIIO::ImageBufAlgo::resize(
      src, {OIIO::ParamValue("filtername", "box"), OIIO::ParamValue("filterwidth", 1.0f)}, roi);
#else
  return OIIO::ImageBufAlgo::resize(src, "box", 1.0f, roi);
#endif
}

}  // namespace spectralize
