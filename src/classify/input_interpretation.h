#pragma once
// What an input image is (docs/DESIGN.md §9): which channels are colour and which is alpha, its
// colour space, whether it is colour at all (a normal map is data) and whether it is light or a
// surface, each with the reason, never a silent guess. Metadata the config cannot honour (an
// ICC profile or a PNG gamma without a matching space) is named in a warning together with the
// space assumed instead.

#include <OpenImageIO/imageio.h>

#include <string>
#include <vector>

#include "colour/colour_space.h"
#include "settings/map_kind.h"
#include "settings/settings.h"
#include "spectralize/core/spectralizer.h"

namespace spectralize {

/// The channels of a colour image.
struct ChannelRoles {
  std::vector<int> colour;           // R, G, B (by name), or one channel (grey)
  int alpha = -1;                    // "A" (or OIIO's alpha channel), -1 for none
  std::vector<std::string> ignored;  // any other channels (e.g. Z), named in a warning
  /// True for a single grey channel (replicated to R = G = B). Cost: O(1).
  bool grey() const { return colour.size() == 1; }
};

struct InputInterpretation {
  ChannelRoles channels;
  std::string colorspace, colorspace_reason;
  std::string contradiction;  // a given space the file's own statement disagrees with, or ""
  const ColourSpaceFacts* facts = nullptr;  // of `colorspace`: what the converters and tags use
  NameVerdict name;                         // what the words of its name and folders say
  std::string data_reason;                  // non-empty: non-colour data (by name or colour space)
  Mode mode = Mode::emission;
  std::string mode_reason;            // (interpret_input only)
  std::vector<std::string> warnings;  // for people, each naming the file
};

/// The colour and alpha channels of `spec`: R, G, B (any order, optionally A), or a single grey
/// channel (Y, or the only channel), optionally with A. Throws Error naming `file` for an
/// already spectral image, a lone named layer (diffuse.R, ...), two colour channels, or any
/// other set that is not colour. Cost: O(channels).
ChannelRoles colour_channels(const OIIO::ImageSpec& spec, const std::string& file);

/// The description in an ICC profile's 'desc' tag (v2 'desc' or v4 'mluc'), or "" if the
/// profile has none or is malformed. Never throws. Cost: O(profile).
std::string icc_description(const unsigned char* data, std::size_t size);

/// Decides channels, colour space and data or colour of an input (`file` names it, anchors the
/// config's file rules and gives the words of its name). Colour space, first that applies: the
/// settings; the file's metadata (EXR chromaticities matched after adapting their white to D65,
/// colorInteropID, ICC profile, PNG gAMA, oiio:ColorSpace beyond OIIO's generic defaults),
/// refined by a file rule that agrees, overruled by a file rule naming a data space, a
/// disagreeing rule warned; the config's file rules; the format's convention (Radiance HDR:
/// linear Rec.709; PNG, JPEG: sRGB); the config's role for the data type (scene_linear for
/// float; matte_paint, color_picking, texture_paint for integers). Data: a data word of the
/// name or its folders (map_kind.h), else a data colour space. Throws Error (naming the file)
/// when nothing applies or a named space is unknown. Cost: reading `file`'s first chunks for
/// PNG metadata, OCIO look-ups (no pixels).
InputInterpretation interpret_colour(const std::string& file, const OIIO::ImageSpec& spec,
                                     const Settings& settings, const ColourSpaces& spaces);

/// What is said when the values of a data colour space (`space`, raw or non-colour in the
/// config) are converted anyway, for an image, a --color or an array of colours alike: they
/// are taken as CIE XYZ. Cost: O(1).
std::string data_space_warning(const std::string& space);

/// interpret_colour, then light or surface by decide_mode (light_or_surface.h), with a warning
/// for data converted anyway. Cost: interpret_colour, plus reading the image when no earlier
/// clue decides its mode (float data without a light or surface word).
InputInterpretation interpret_input(const std::string& file, const OIIO::ImageSpec& spec,
                                    const Settings& settings, const ColourSpaces& spaces);

/// The light-or-surface half of interpret_input for an interpretation interpret_colour made
/// (ingest decides data first, and reads no pixels of a file it skips): sets in.mode and
/// in.mode_reason, adds its warnings. Cost: reading the image when no earlier clue decides.
void decide_light_or_surface(InputInterpretation& in, const std::string& file,
                             const OIIO::ImageSpec& spec, const Settings& settings,
                             const ColourSpaces& spaces);

/// The settings as resolved for one file: its mode and colour space as `in` decided them, and
/// the preview colour space (settings.preview_colorspace resolved, else the config's
/// scene_linear role). What its header records and what ingest's up-to-date key hashes
/// (file_settings). Throws Error for an unknown preview space. Cost: an OCIO look-up.
Settings resolved_settings(const Settings& settings, const InputInterpretation& in,
                           const ColourSpaces& spaces);

/// The config's default space for float (scene_linear) or integer data (matte_paint,
/// color_picking, texture_paint), with the role that gave it; throws Error naming the config
/// when it has none of them. Cost: O(1).
std::pair<std::string, std::string> default_colour_space(const ColourSpaces& spaces,
                                                         bool float_data);

}  // namespace spectralize
