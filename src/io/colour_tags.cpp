#include "io/colour_tags.h"

namespace spectralize {

void drop_colour_tags(OIIO::ImageSpec& spec) {
  // Names are regular expressions: "ICCProfile.*" also takes OIIO's decoded header fields.
  for (const char* name : {"chromaticities", "colorInteropID", "oiio:ColorSpace", "oiio:Gamma",
                           "ICCProfile.*", "colorspace"})
    spec.erase_attribute(name);
}

void tag_colour_space(OIIO::ImageSpec& spec, const ColourSpaces& spaces, const std::string& space) {
  drop_colour_tags(spec);
  spec.attribute("oiio:ColorSpace", space);
  const std::string id = spaces.interop_id(space);
  if (!id.empty()) spec.attribute("colorInteropID", id);
  if (!spaces.is_data(space) && spaces.is_linear(space))
    if (const auto xy = spaces.chromaticities(space))
      spec.attribute("chromaticities", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8), xy->data());
}

}  // namespace spectralize
