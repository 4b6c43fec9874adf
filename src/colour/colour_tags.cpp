#include "colour/colour_tags.h"

#include "colour/icc_profile.h"
#include "imagefile/oiio_compat.h"
#include "imagefile/output_formats.h"
#include "text/strings.h"

namespace spectralize {

void drop_colour_tags(OIIO::ImageSpec& spec) {
  // Names are regular expressions: "ICCProfile.*" also takes OIIO's decoded header fields.
  for (const char* name : {"chromaticities", "colorInteropID", "oiio:ColorSpace", "oiio:Gamma",
                           "ICCProfile.*", "colorspace"})
    spec.erase_attribute(name);
}

std::vector<std::string> tag_colour_space(OIIO::ImageSpec& spec, const ColourSpaces& spaces,
                                          const std::string& space, const std::string& format,
                                          const std::string& file) {
  drop_colour_tags(spec);
  const ColourSpaceFacts& facts = spaces.facts(space);
  const std::string& id = facts.interop_id;
  const bool data = facts.data;
  // OIIO 3 names a space by its interop ID here (and its writers act on it: an OpenEXR's
  // colorInteropID, a PNG's gAMA or cICP); OIIO 2 keeps the config's name.
  spec.attribute("oiio:ColorSpace",
                 oiio_compat::kInteropColourSpaceNames && !id.empty() && !data ? id : space);
  if (!id.empty()) spec.attribute("colorInteropID", id);
  // Chromaticities describe the primaries and white whatever the transfer (sRGB - Texture
  // has Rec.709's).
  const auto xy = data ? std::nullopt : facts.chromaticities;
  if (xy) spec.attribute("chromaticities", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8), xy->data());
  std::vector<std::string> warnings;
  // Where the format says the space: the output table's slot for it (docs/DESIGN.md §9).
  const OutputFormat* f = output_format_named(format);
  const ColourSlot slot = f ? f->colour : ColourSlot::srgb;
  if (data || slot == ColourSlot::attributes) return warnings;
  // Appended, not "'" + clip(...): GCC 12 sees a bogus overflow in operator+(const char*, &&).
  std::string where(1, '\'');
  where.append(clip(file, 200)).append("': ");
  if (slot == ColourSlot::linear_rec709) {
    // RGBE says only "linear"; readers take Rec.709 primaries and a D65 white.
    if (id != "lin_rec709_scene")
      warnings.push_back(where + std::string(f->label) + " has no slot for the colour space '" +
                         space +
                         "'; readers will assume linear Rec.709 (sRGB primaries): write "
                         "OpenEXR, or --colorspace a linear Rec.709 space");
    return warnings;
  }
  if (slot != ColourSlot::icc_profile) {
    if (id == "srgb_rec709_scene") return warnings;  // what readers assume anyway
    warnings.push_back(where + "the " + std::string(f ? f->label : format) +
                       " format has no slot for the colour space '" + space +
                       "'; readers will assume sRGB: write OpenEXR, TIFF, PNG or JPEG");
    return warnings;
  }
  const auto& transfer = facts.transfer;
  std::vector<unsigned char> icc;
  if (xy && transfer)
    icc = icc_profile(*xy, *transfer, id.empty() ? space : space + " (" + id + ")");
  if (icc.empty()) {
    warnings.push_back(where + "no ICC profile states the colour space '" + space +
                       "' (its transfer function is not linear, the sRGB curve or a pure gamma, "
                       "or it has no RGB primaries); readers will assume sRGB");
    return warnings;
  }
  spec.attribute("ICCProfile", OIIO::TypeDesc(OIIO::TypeDesc::UINT8, icc.size()), icc.data());
  return warnings;
}

}  // namespace spectralize
