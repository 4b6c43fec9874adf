#pragma once
// Every RGB spectralize writes says what it is (docs/DESIGN.md §9): the attributes OIIO,
// OCIO-aware tools and pbrt-v4 read, set from the OCIO config's own definition of the space,
// and for formats with no such attributes an ICC profile; where a format has no slot for the
// space at all, a warning says what readers will assume.

#include <OpenImageIO/imageio.h>

#include <string>
#include <vector>

#include "colour/colour_space.h"

namespace spectralize {

/// Removes every colour tag `spec` carries over from elsewhere (chromaticities,
/// colorInteropID, oiio:ColorSpace, ICC profiles, gamma). Cost: O(attributes).
void drop_colour_tags(OIIO::ImageSpec& spec);

/// Tags `spec`'s RGB as `space` for a file of OIIO format `format` ("openexr", "tiff", ...)
/// named `file`: oiio:ColorSpace (the config's name; with OIIO 3 its interop ID where known),
/// colorInteropID when the space has one (the config's, or measured for a known one),
/// chromaticities when it has RGB primaries (whatever its transfer; not for data), and for TIFF,
/// PNG and JPEG an ICC profile of its primaries, white and transfer when an ICC curve states it.
/// Replaces any earlier tags. Returns warnings naming `file` and what readers will assume when the
/// format cannot say the space (Radiance HDR beyond linear Rec.709, an unknown transfer, formats
/// without ICC profiles). Cost: a few OCIO processors, ~1 ms.
std::vector<std::string> tag_colour_space(OIIO::ImageSpec& spec, const ColourSpaces& spaces,
                                          const std::string& space,
                                          const std::string& format = "openexr",
                                          const std::string& file = "");

}  // namespace spectralize
