#include "io/input_interpretation.h"

#include <OpenImageIO/strutil.h>

#include <algorithm>
#include <cmath>
#include <fstream>

#include "core/error.h"
#include "io/safe_output.h"
#include "io/spectral_layout.h"

namespace spectralize {

namespace {

std::uint32_t be32(const unsigned char* p) {
  return (std::uint32_t(p[0]) << 24) | (std::uint32_t(p[1]) << 16) | (std::uint32_t(p[2]) << 8) |
         std::uint32_t(p[3]);
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// The first of `names` the config knows whose interop ID is `id` (so an alias meaning
// something else in a studio config is not taken), else any space of the config with that ID.
std::string find_space(const ColourSpaces& spaces, const std::string& id,
                       std::initializer_list<const char*> names) {
  for (const char* name : names) {
    try {
      const std::string space = spaces.resolve(name);
      if (spaces.interop_id(space) == id) return space;
    } catch (const Error&) {
    }
  }
  for (const std::string& space : spaces.names()) {
    try {
      if (spaces.interop_id(space) == id) return space;
    } catch (const Error&) {
    }
  }
  return "";
}

// PNG colour chunks OIIO 2.4 does not report: cHRM (primaries and white, 8 x 1e-5 units).
struct PngChunks {
  bool chrm = false;
  float xy[8] = {};
};

PngChunks read_png_chunks(const std::string& file) {
  PngChunks out;
  std::ifstream f(file, std::ios::binary);
  unsigned char head[8];
  if (!f.read(reinterpret_cast<char*>(head), 8) || head[1] != 'P' || head[2] != 'N') return out;
  // Colour chunks come before the first IDAT; stop there (or after 1 MB of other chunks).
  for (std::size_t read = 8; read < (1u << 20);) {
    unsigned char h[8];
    if (!f.read(reinterpret_cast<char*>(h), 8)) break;
    const std::uint32_t length = be32(h);
    const std::string type(reinterpret_cast<char*>(h + 4), 4);
    if (type == "IDAT" || type == "IEND" || length > (1u << 20)) break;
    std::vector<unsigned char> data(length + 4);
    if (!f.read(reinterpret_cast<char*>(data.data()), length + 4)) break;
    if (type == "cHRM" && length == 32) {
      out.chrm = true;
      // Order in the chunk: white, red, green, blue; ours: red, green, blue, white.
      const int to[4] = {6, 0, 2, 4};
      for (int i = 0; i < 4; ++i) {
        out.xy[to[i]] = be32(&data[8 * i]) / 1e5f;
        out.xy[to[i] + 1] = be32(&data[8 * i + 4]) / 1e5f;
      }
    }
    read += 12 + length;
  }
  return out;
}

bool same_xy(const float* a, const float* b) {
  for (int i = 0; i < 8; ++i)
    if (std::abs(a[i] - b[i]) > 2e-3f) return false;
  return true;
}

constexpr float kRec709[8] = {0.64f, 0.33f, 0.30f, 0.60f, 0.15f, 0.06f, 0.3127f, 0.3290f};

// The space the file's own metadata names, with the reason, or {"", ""}.
std::pair<std::string, std::string> metadata_space(const std::string& file,
                                                   const OIIO::ImageSpec& spec,
                                                   const ColourSpaces& spaces,
                                                   const std::string& fallback,
                                                   std::vector<std::string>& warnings) {
  const std::string where = "'" + clip(file, 200) + "': ";
  // EXR chromaticities: the most specific statement a file makes about its primaries.
  if (const OIIO::ParamValue* chroma =
          spec.find_attribute("chromaticities", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8))) {
    const float* c = static_cast<const float*>(chroma->data());
    if (const std::string id = interop_id_of_chromaticities(c); !id.empty()) {
      const std::string space = find_space(spaces, id, {});
      if (!space.empty()) return {space, "EXR chromaticities of " + space};
    }
    for (const std::string& space : spaces.names()) {
      if (spaces.is_data(space) || !spaces.is_linear(space)) continue;
      const auto xy = spaces.chromaticities(space);
      if (xy && same_xy(c, xy->data())) return {space, "EXR chromaticities of " + space};
    }
    warnings.push_back(where +
                       "its EXR chromaticities match no linear colour space of the OCIO "
                       "config; assumed '" +
                       fallback + "' (give --colorspace to choose)");
  }
  // The colour interop ID of OCIO 2 configs, if a writer set one.
  const std::string interop = spec.get_string_attribute("colorInteropID");
  if (!interop.empty()) {
    const std::string space = find_space(spaces, interop, {});
    if (!space.empty()) return {space, "file metadata colorInteropID '" + interop + "'"};
    warnings.push_back(where + "its colorInteropID '" + clip(interop) +
                       "' matches no colour space of the OCIO config; assumed '" + fallback + "'");
  }
  // An embedded ICC profile, by its description.
  if (const OIIO::ParamValue* icc = spec.find_attribute("ICCProfile")) {
    const std::string desc =
        icc_description(static_cast<const unsigned char*>(icc->data()), icc->datasize());
    // Only the descriptions the standard profiles carry: a variant ("sRGB ... Linear",
    // "DCI-P3") has other primaries, white or curve, so it is named in a warning instead.
    const std::string d = lower(std::string(OIIO::Strutil::strip(desc)));
    auto one_of = [&](std::initializer_list<const char*> names) {
      for (const char* n : names)
        if (d == n) return true;
      return false;
    };
    std::string space;
    // spectralize's own profiles end in the space's interop ID: "ACEScg (lin_ap1_scene)".
    if (const std::size_t open = desc.rfind(" ("); open != std::string::npos && desc.back() == ')')
      space = find_space(spaces, desc.substr(open + 2, desc.size() - open - 3), {});
    if (!space.empty()) {
    } else if (one_of({"srgb", "srgb iec61966-2.1", "srgb iec61966-2-1", "srgb built-in",
                       "srgb iec61966-2.1 (equivalent)", "srgb profile"}))
      space = find_space(spaces, "srgb_rec709_scene", {"sRGB - Texture", "srgb_tx"});
    else if (one_of({"adobe rgb (1998)", "adobergb1998", "compatible with adobe rgb (1998)",
                     "adobe rgb"}))
      space = find_space(spaces, "g22_adobergb_scene", {"Adobe RGB (1998) - Texture"});
    else if (one_of({"display p3", "displayp3"}))
      space = find_space(spaces, "srgb_p3d65_scene", {"Display P3 - Texture"});
    if (!space.empty()) return {space, "embedded ICC profile '" + clip(desc) + "'"};
    warnings.push_back(where + "its embedded ICC profile '" +
                       clip(desc.empty() ? std::string("(no description)") : desc) +
                       "' is not honoured (no matching colour space in the OCIO config); "
                       "assumed '" +
                       fallback + "'");
  }
  // PNG gAMA (OIIO's oiio:Gamma) and cHRM.
  const bool png = OIIO::Strutil::iends_with(file, ".png");
  if (png) {
    const PngChunks chunks = read_png_chunks(file);
    if (chunks.chrm && !same_xy(chunks.xy, kRec709)) {
      warnings.push_back(where + "its PNG cHRM primaries (" +
                         OIIO::Strutil::fmt::format("{:.3f},{:.3f} {:.3f},{:.3f} {:.3f},{:.3f}",
                                                    chunks.xy[0], chunks.xy[1], chunks.xy[2],
                                                    chunks.xy[3], chunks.xy[4], chunks.xy[5]) +
                         ") are not honoured; assumed Rec.709 primaries");
    }
  }
  if (const OIIO::ParamValue* g = spec.find_attribute("oiio:Gamma"); g && png) {
    const float gamma = spec.get_float_attribute("oiio:Gamma", 0);
    std::string space;
    if (std::abs(gamma - 1.0f) < 0.01f)
      space = find_space(spaces, "lin_rec709_scene", {"Linear Rec.709 (sRGB)", "lin_rec709"});
    else if (std::abs(gamma - 2.2f) < 0.01f)
      space = find_space(spaces, "g22_rec709_scene", {"Gamma 2.2 Rec.709 - Texture"});
    const std::string tag = OIIO::Strutil::fmt::format("PNG gAMA (gamma {:g})", gamma);
    if (space.empty() && std::abs(gamma - 2.2f) < 0.01f) {
      // A gamma-2.2 space is rare in studio configs; the sRGB curve is within 1% of it.
      space = find_space(spaces, "srgb_rec709_scene", {"sRGB - Texture", "srgb_tx"});
      if (!space.empty())
        warnings.push_back(where + "its " + tag +
                           " has no matching space in the OCIO config; read as '" + space + "'");
    }
    if (!space.empty()) return {space, "file metadata " + tag};
    warnings.push_back(where + "its " + tag +
                       " is not honoured (no matching colour space in "
                       "the OCIO config); assumed '" +
                       fallback + "'");
  }
  // OIIO reports "Linear" for every EXR and "sRGB" for every PNG without colour metadata: only
  // a name beyond those generic defaults is a statement about this file.
  const std::string meta = spec.get_string_attribute("oiio:ColorSpace");
  const bool generic = OIIO::Strutil::iequals(meta, "linear") ||
                       OIIO::Strutil::iequals(meta, "srgb") ||
                       OIIO::Strutil::istarts_with(meta, "GammaCorrected");
  if (!meta.empty() && !generic) {
    try {
      return {spaces.resolve(meta), "file metadata oiio:ColorSpace '" + meta + "'"};
    } catch (const Error&) {
      warnings.push_back(where + "its colour space '" + clip(meta) +
                         "' is not in the OCIO config; assumed '" + fallback + "'");
    }
  }
  return {"", ""};
}

}  // namespace

std::string icc_description(const unsigned char* data, std::size_t size) {
  if (!data || size < 132) return "";
  const std::uint32_t count = be32(data + 128);
  for (std::uint32_t i = 0; i < count && 132 + 12 * (i + 1) <= size; ++i) {
    const unsigned char* entry = data + 132 + 12 * i;
    if (std::string(reinterpret_cast<const char*>(entry), 4) != "desc") continue;
    const std::uint32_t offset = be32(entry + 4), length = be32(entry + 8);
    if (offset > size || length > size - offset || length < 12) return "";
    const unsigned char* tag = data + offset;
    const std::string type(reinterpret_cast<const char*>(tag), 4);
    std::string out;
    if (type == "desc") {  // v2: ASCII count, then the text with its NUL
      const std::uint32_t n = be32(tag + 8);
      for (std::uint32_t k = 0; k < n && 12 + k < length && tag[12 + k]; ++k)
        out += static_cast<char>(tag[12 + k]);
    } else if (type == "mluc" && length >= 28) {  // v4: the first record, UTF-16BE
      const std::uint32_t n = be32(tag + 20), at = be32(tag + 24);
      for (std::uint32_t k = 0; k + 1 < n && at + k + 1 < length; k += 2) {
        const unsigned c = (unsigned(tag[at + k]) << 8) | tag[at + k + 1];
        out += c < 128 ? static_cast<char>(c) : '?';
      }
    }
    return out;
  }
  return "";
}

ChannelRoles colour_channels(const OIIO::ImageSpec& spec, const std::string& file) {
  const std::string where = "'" + clip(file, 200) + "': ";
  ChannelRoles roles;
  std::vector<std::string> names;
  for (int c = 0; c < spec.nchannels; ++c) names.emplace_back(spec.channel_name(c));
  auto index = [&](const char* name) {
    auto it = std::find(names.begin(), names.end(), name);
    return it == names.end() ? -1 : static_cast<int>(it - names.begin());
  };
  for (const std::string& n : names)
    if (parse_spectral_channel(n))
      throw Error(where + "is already a spectral image (channel '" + clip(n) +
                  "'); use --to-rgb to turn it into RGB");
  const int r = index("R"), g = index("G"), b = index("B"), y = index("Y");
  roles.alpha = index("A");
  if (roles.alpha < 0 && spec.alpha_channel >= 0 && spec.alpha_channel < spec.nchannels &&
      spec.alpha_channel != r && spec.alpha_channel != g && spec.alpha_channel != b)
    roles.alpha = spec.alpha_channel;
  if (r >= 0 && g >= 0 && b >= 0) {
    roles.colour = {r, g, b};
  } else if (r < 0 && g < 0 && b < 0 && (y >= 0 || spec.nchannels - (roles.alpha >= 0) == 1)) {
    // Luminance "Y", or a lone channel (with or without alpha): grey.
    roles.colour = {y >= 0 ? y : (roles.alpha == 0 ? 1 : 0)};
  } else {
    std::string list;
    for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
    throw Error(where + "its channels (" + clip(list, 200) +
                ") are not an RGB, RGBA, grey or grey + alpha image; pick the colour channels "
                "first, e.g. oiiotool IN --ch R=<layer>.R,G=<layer>.G,B=<layer>.B -o rgb.exr");
  }
  for (int c = 0; c < spec.nchannels; ++c)
    if (c != roles.alpha &&
        std::find(roles.colour.begin(), roles.colour.end(), c) == roles.colour.end())
      roles.ignored.push_back(names[c]);
  return roles;
}

std::pair<std::string, std::string> default_colour_space(const ColourSpaces& spaces,
                                                         bool float_data) {
  // Float data is scene-linear light; integer data is a painted or photographed texture, whose
  // encoding matte_paint and color_picking name in ACES-style configs (texture_paint is often a
  // log space there, so it comes last).
  const std::vector<const char*> roles =
      float_data ? std::vector<const char*>{"scene_linear"}
                 : std::vector<const char*>{"matte_paint", "color_picking", "texture_paint"};
  for (const char* role : roles) {
    const std::string space = spaces.role(role);
    if (!space.empty()) return {space, std::string("the config's ") + role + " role"};
  }
  throw ConfigError(
      "the OCIO config '" + spaces.origin() + "' has no " +
      (float_data ? "scene_linear role" : "matte_paint, color_picking or texture_paint role") +
      " to choose a default colour space: give --colorspace");
}

InputInterpretation interpret_input(const std::string& file, const OIIO::ImageSpec& spec,
                                    const Settings& settings, const ColourSpaces& spaces) {
  InputInterpretation in;
  const std::string where = "'" + clip(file, 200) + "': ";
  in.channels = colour_channels(spec, file);
  if (!in.channels.ignored.empty()) {
    std::string list;
    for (const std::string& n : in.channels.ignored) list += (list.empty() ? "" : ", ") + n;
    in.warnings.push_back(where + "channels " + clip(list, 200) +
                          " are not colour and are not written");
  }
  const bool float_data = spec.format.is_floating_point();
  // Colour space: the command line, the config's file rules, the file, the config's roles.
  if (!settings.colorspace.empty()) {
    in.colorspace = spaces.resolve(settings.colorspace);
    in.colorspace_reason = "--colorspace";
  } else if (auto [ruled, rule] = spaces.file_rule(file); !ruled.empty()) {
    in.colorspace = ruled;
    in.colorspace_reason = "the config's file rule '" + rule + "'";
  } else {
    const auto [fallback, role] = default_colour_space(spaces, float_data);
    auto [space, reason] = metadata_space(file, spec, spaces, fallback, in.warnings);
    if (space.empty()) {
      space = fallback;
      reason =
          (float_data ? "default for floating-point data: " : "default for integer data: ") + role;
    }
    in.colorspace = space;
    in.colorspace_reason = reason;
  }
  if (spaces.is_data(in.colorspace))
    in.warnings.push_back(where + "colour space '" + in.colorspace +
                          "' is marked as data (not colour) in the OCIO config; its values are "
                          "taken as CIE XYZ");
  // Mode: the command line, else the data type.
  switch (settings.mode) {
    case ModeChoice::emission:
      in.mode = Mode::emission;
      in.mode_reason = "--mode";
      break;
    case ModeChoice::reflectance:
      in.mode = Mode::reflectance;
      in.mode_reason = "--mode";
      break;
    case ModeChoice::automatic:
      in.mode = float_data ? Mode::emission : Mode::reflectance;
      in.mode_reason = float_data ? "auto: floating-point data is light (emission)"
                                  : "auto: integer data is a texture (reflectance)";
      break;
  }
  return in;
}

Settings resolved_settings(const Settings& settings, const InputInterpretation& in,
                           const ColourSpaces& spaces) {
  Settings s = settings;
  s.spectral.mode = in.mode;
  s.colorspace = in.colorspace;
  s.preview_colorspace = settings.preview_colorspace.empty()
                             ? default_colour_space(spaces, true).first
                             : spaces.resolve(settings.preview_colorspace);
  return s;
}

}  // namespace spectralize
