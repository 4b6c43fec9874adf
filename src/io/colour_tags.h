#pragma once
// Every RGB spectralize writes says what it is (docs/DESIGN.md §9): the attributes OIIO,
// OCIO-aware tools and pbrt-v4 read, set from the OCIO config's own definition of the space.

#include <OpenImageIO/imageio.h>

#include <string>

#include "io/colour_space.h"

namespace spectralize {

/// Removes every colour tag `spec` carries over from elsewhere (chromaticities,
/// colorInteropID, oiio:ColorSpace, ICC profiles, gamma). Cost: O(attributes).
void drop_colour_tags(OIIO::ImageSpec& spec);

/// Tags `spec`'s RGB as `space`: oiio:ColorSpace (the config's name), colorInteropID when the
/// space matches a known one, and chromaticities when it is linear with RGB primaries (not for
/// data). Replaces any earlier tags. Cost: an OCIO processor or two.
void tag_colour_space(OIIO::ImageSpec& spec, const ColourSpaces& spaces, const std::string& space);

}  // namespace spectralize
