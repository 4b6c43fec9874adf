#include "classify/input_interpretation.h"

#include <OpenImageIO/strutil.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>

#include "classify/light_or_surface.h"
#include "imagefile/oiio_compat.h"
#include "imagefile/spectral_channel.h"
#include "spectralize/core/error.h"
#include "text/strings.h"

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

// A PNG's colour chunks, read by spectralize itself: OIIO 2.4 does not report cHRM, and OIIO 3
// reports gAMA 1.0 only through its own reading of the chunks ("lin_rec709_scene").
struct PngChunks {
  bool chrm = false;
  float xy[8] = {};   // cHRM: primaries and white, 8 x 1e-5 units
  bool srgb = false;  // sRGB: the sRGB curve, whatever gAMA says (the PNG standard)
  float gamma = 0;    // gAMA, as the exponent that decodes (2.2 for a stored 45455), or 0
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
    if (type == "sRGB") out.srgb = true;
    if (type == "gAMA" && length == 4 && be32(&data[0]) > 0)
      out.gamma = 100000.0f / static_cast<float>(be32(&data[0]));
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

std::string fmt_xy(const float* xy) {
  return OIIO::Strutil::fmt::format("{:.4f},{:.4f} {:.4f},{:.4f} {:.4f},{:.4f} white {:.4f},{:.4f}",
                                    xy[0], xy[1], xy[2], xy[3], xy[4], xy[5], xy[6], xy[7]);
}

// What the file's own metadata says about its colour space.
struct Stated {
  std::string space, reason;
  bool primaries_only = false;  // EXR chromaticities: primaries and white, not the encoding
  explicit operator bool() const { return !space.empty(); }
};

// The linear space of the config whose D65-adapted primaries are closest to the file's
// chromaticities (within kChromaticityTolerance), preferring the config's scene_linear role
// and a space of the known standard; "" when none is.
Stated space_of_chromaticities(const float* xy, const ColourSpaces& spaces) {
  const std::array<float, 8> adapted = adapt_chromaticities_to_d65(xy);
  const bool d65 = std::abs(xy[6] - kD65x) < 5e-4f && std::abs(xy[7] - kD65y) < 5e-4f;
  auto reason = [&](const std::string& space, double diff) {
    std::string r = "EXR chromaticities (" + fmt_xy(xy) + ") of '" + space + "'";
    if (!d65)
      r += OIIO::Strutil::fmt::format(
          " after Bradford adaptation of their white to D65 (primaries within {:.1e})", diff);
    return r;
  };
  // A known standard's primaries: the space with that interop ID.
  if (const std::string id = interop_id_of_chromaticities(xy); !id.empty()) {
    const std::string space = spaces.space_of_interop_id(id);
    if (!space.empty()) {
      const auto p = spaces.primaries_d65(space);
      return {space, reason(space, p ? chromaticity_difference(p->data(), adapted.data()) : 0),
              true};
    }
  }
  // Any linear space of the config with those primaries.
  std::string best;
  double best_diff = kChromaticityTolerance;
  for (const std::string& space : spaces.names()) {
    try {
      const ColourSpaceFacts& f = spaces.facts(space);
      if (f.data || f.display_referred || !f.linear) continue;
      const auto p = spaces.primaries_d65(space);
      if (!p) continue;
      const double d = chromaticity_difference(p->data(), adapted.data());
      if (d <= best_diff) best = space, best_diff = d;
    } catch (const Error&) {
    }
  }
  if (best.empty()) return {};
  return {best, reason(best, best_diff), true};
}

// The space the file's own metadata names, with the reason, or nothing. `fallback` is named
// in the warnings about metadata that is not honoured.
Stated metadata_space(const std::string& file, const OIIO::ImageSpec& spec,
                      const ColourSpaces& spaces, const std::string& fallback,
                      std::vector<std::string>& warnings) {
  const std::string where = "'" + clip(file, 200) + "': ";
  // The names the file gives its own space: preferred among spaces of the same interop ID.
  std::vector<std::string> named;
  const std::string meta = spec.get_string_attribute("oiio:ColorSpace");
  // OIIO 2 reports "Linear" for every EXR and "sRGB" for every PNG without colour metadata;
  // OIIO 3 reports an interop ID it derives from what the file says (its colorInteropID, a
  // PNG's chunks, a TIFF's Exif colour space), which is read here directly. Only a name beyond
  // those is a statement of its own about this file.
  const bool generic = OIIO::Strutil::iequals(meta, "linear") ||
                       OIIO::Strutil::iequals(meta, "srgb") ||
                       OIIO::Strutil::istarts_with(meta, "GammaCorrected") ||
                       (oiio_compat::kInteropColourSpaceNames && looks_like_interop_id(meta));
  if (!meta.empty() && !generic) named.push_back(meta);
  std::string desc;
  const OIIO::ParamValue* icc = spec.find_attribute("ICCProfile");
  if (icc) {
    desc = icc_description(static_cast<const unsigned char*>(icc->data()), icc->datasize());
    // spectralize's own profiles: "<the space's name> (<its interop ID>)".
    if (const std::size_t open = desc.rfind(" ("); open != std::string::npos && desc.back() == ')')
      named.push_back(desc.substr(0, open));
  }
  // EXR chromaticities: the most specific statement a file makes about its primaries.
  if (const OIIO::ParamValue* chroma =
          spec.find_attribute("chromaticities", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8))) {
    const float* c = static_cast<const float*>(chroma->data());
    // A space the file names with these primaries is the more precise statement.
    for (const std::string& name : named) {
      try {
        const std::string space = spaces.resolve(name);
        const auto p = spaces.primaries_d65(space);
        const auto adapted = adapt_chromaticities_to_d65(c);
        if (p && chromaticity_difference(p->data(), adapted.data()) <= kChromaticityTolerance)
          return {space,
                  "file metadata oiio:ColorSpace '" + name + "' (its EXR chromaticities agree)",
                  false};
      } catch (const Error&) {
      }
    }
    if (Stated s = space_of_chromaticities(c, spaces)) return s;
    warnings.push_back(where + "its EXR chromaticities (" + fmt_xy(c) +
                       ") match no linear colour space of the OCIO config, even after adapting "
                       "their white to D65; assumed '" +
                       fallback + "' (give --colorspace to choose)");
  }
  // The colour interop ID of OCIO 2 configs, if a writer set one.
  const std::string interop = spec.get_string_attribute("colorInteropID");
  if (!interop.empty()) {
    std::string space = spaces.space_of_interop_id(interop, named);
    if (!space.empty()) return {space, "file metadata colorInteropID '" + interop + "'", false};
    // A display's output read by a config without display-referred spaces: the scene-referred
    // space of the same encoding holds the same values.
    const std::string suffix = "_display";
    if (interop.size() > suffix.size() &&
        interop.compare(interop.size() - suffix.size(), suffix.size(), suffix) == 0) {
      const std::string scene = interop.substr(0, interop.size() - suffix.size()) + "_scene";
      space = spaces.space_of_interop_id(scene);
      if (!space.empty()) {
        warnings.push_back(
            where + "its colorInteropID '" + clip(interop) +
            "' is display-referred and the OCIO config has no such space; read as '" + space +
            "', the scene-referred space of the same encoding");
        return {space, "file metadata colorInteropID '" + interop + "' (as " + scene + ")", false};
      }
    }
    warnings.push_back(where + "its colorInteropID '" + clip(interop) +
                       "' matches no colour space of the OCIO config; assumed '" + fallback + "'");
  }
  // An embedded ICC profile, by its description.
  if (icc) {
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
      space = spaces.space_of_interop_id(desc.substr(open + 2, desc.size() - open - 3), named);
    if (!space.empty()) {
    } else if (one_of({"srgb", "srgb iec61966-2.1", "srgb iec61966-2-1", "srgb built-in",
                       "srgb iec61966-2.1 (equivalent)", "srgb profile"}))
      space = spaces.space_of_interop_id("srgb_rec709_scene", named);
    else if (one_of({"adobe rgb (1998)", "adobergb1998", "compatible with adobe rgb (1998)",
                     "adobe rgb"}))
      space = spaces.space_of_interop_id("g22_adobergb_scene", named);
    else if (one_of({"display p3", "displayp3"}))
      space = spaces.space_of_interop_id("srgb_p3d65_scene", named);
    if (!space.empty()) return {space, "embedded ICC profile '" + clip(desc) + "'", false};
    warnings.push_back(where + "its embedded ICC profile '" +
                       clip(desc.empty() ? std::string("(no description)") : desc) +
                       "' is not honoured (no matching colour space in the OCIO config); "
                       "assumed '" +
                       fallback + "'");
  }
  // PNG gAMA (unless an sRGB chunk overrules it) and cHRM.
  const bool png = OIIO::Strutil::iends_with(file, ".png");
  const PngChunks chunks = png ? read_png_chunks(file) : PngChunks{};
  if (png) {
    if (chunks.chrm && chromaticity_difference(chunks.xy, known_primaries().front().native.data()) >
                           kChromaticityTolerance) {
      warnings.push_back(where + "its PNG cHRM primaries (" +
                         OIIO::Strutil::fmt::format("{:.3f},{:.3f} {:.3f},{:.3f} {:.3f},{:.3f}",
                                                    chunks.xy[0], chunks.xy[1], chunks.xy[2],
                                                    chunks.xy[3], chunks.xy[4], chunks.xy[5]) +
                         ") are not honoured; assumed Rec.709 primaries");
    }
  }
  if (png && chunks.gamma > 0 && !chunks.srgb) {
    const float gamma = chunks.gamma;
    std::string space;
    if (std::abs(gamma - 1.0f) < 0.01f)
      space = spaces.space_of_interop_id("lin_rec709_scene", named);
    else if (std::abs(gamma - 2.2f) < 0.01f)
      space = spaces.space_of_interop_id("g22_rec709_scene", named);
    const std::string tag = OIIO::Strutil::fmt::format("PNG gAMA (gamma {:g})", gamma);
    if (space.empty() && std::abs(gamma - 2.2f) < 0.01f) {
      // A gamma-2.2 space is rare in studio configs; the sRGB curve is within 1% of it.
      space = spaces.space_of_interop_id("srgb_rec709_scene", named);
      if (!space.empty())
        warnings.push_back(where + "its " + tag +
                           " has no matching space in the OCIO config; read as '" + space + "'");
    }
    if (!space.empty()) return {space, "file metadata " + tag, false};
    warnings.push_back(where + "its " + tag +
                       " is not honoured (no matching colour space in "
                       "the OCIO config); assumed '" +
                       fallback + "'");
  }
  if (!meta.empty() && !generic) {
    try {
      return {spaces.resolve(meta), "file metadata oiio:ColorSpace '" + meta + "'", false};
    } catch (const Error&) {
      warnings.push_back(where + "its colour space '" + clip(meta) +
                         "' is not in the OCIO config; assumed '" + fallback + "'");
    }
  }
  return {};
}

// What a format's own convention says about untagged files: Radiance RGBE holds linear
// Rec.709 (every reader assumes it: the format has no other slot); PNG and JPEG are sRGB.
Stated format_convention(const std::string& file, bool float_data, const ColourSpaces& spaces,
                         std::vector<std::string>& warnings, const std::string& fallback) {
  const std::string ext = lower(std::filesystem::path(file).extension().string());
  if (ext == ".hdr" || ext == ".rgbe" || ext == ".pic") {
    const std::string space = spaces.space_of_interop_id("lin_rec709_scene");
    if (!space.empty())
      return {space, "Radiance HDR: linear Rec.709 by the format's convention", false};
    warnings.push_back("'" + clip(file, 200) +
                       "': Radiance HDR files are linear Rec.709 by convention, but the OCIO "
                       "config has no linear Rec.709 space; assumed '" +
                       fallback + "'");
    return {};
  }
  if (!float_data &&
      (ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".jpe" || ext == ".jfif")) {
    const std::string space = spaces.space_of_interop_id("srgb_rec709_scene");
    if (!space.empty())
      return {space,
              std::string(ext == ".png" ? "PNG" : "JPEG") +
                  " without colour metadata: sRGB by the format's convention",
              false};
  }
  return {};
}

// Whether a file rule's space says what the metadata says: the same primaries for EXR
// chromaticities (which leave the encoding open), the same interop ID or space otherwise.
bool agrees(const ColourSpaces& spaces, const std::string& rule_space, const Stated& meta) {
  if (rule_space == meta.space) return true;
  try {
    if (meta.primaries_only) {
      const auto a = spaces.primaries_d65(rule_space), b = spaces.primaries_d65(meta.space);
      return a && b && chromaticity_difference(a->data(), b->data()) <= kChromaticityTolerance;
    }
    const std::string& id = spaces.facts(rule_space).interop_id;
    return !id.empty() && id == spaces.facts(meta.space).interop_id;
  } catch (const Error&) {
    return false;
  }
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
  // encoding matte_paint and color_picking name in ACES-style configs. A role the config says
  // is a log encoding is passed over while another role names a texture's encoding (ACES 1.3
  // configs make texture_paint ACEScct, the ACES 2.0 ones matte_paint).
  const std::vector<const char*> roles =
      float_data ? std::vector<const char*>{"scene_linear"}
                 : std::vector<const char*>{"matte_paint", "color_picking", "texture_paint"};
  std::string passed;
  for (const bool allow_log : {false, true}) {
    for (const char* role : roles) {
      const std::string space = spaces.role(role);
      if (space.empty()) continue;
      const bool log = !float_data && spaces.facts(space).encoding == "log";
      if (log && !allow_log) {
        if (passed.empty()) passed = std::string(role) + ", '" + space + "', is a log encoding";
        continue;
      }
      // The config's own choice: a space no colour converts through is its mistake.
      if (const std::string& why = spaces.facts(space).unusable; !why.empty())
        throw ConfigError("the OCIO config '" + spaces.origin() + "' gives its " + role +
                          " role the colour space '" + space + "', which cannot be used: " + why +
                          "; give --colorspace");
      return {space, std::string("the config's ") + role + " role" +
                         (passed.empty() || allow_log ? "" : " (its " + passed + ")")};
    }
  }
  throw ConfigError(
      "the OCIO config '" + spaces.origin() + "' has no " +
      (float_data ? "scene_linear role" : "matte_paint, color_picking or texture_paint role") +
      " to choose a default colour space: give --colorspace");
}

InputInterpretation interpret_colour(const std::string& file, const OIIO::ImageSpec& spec,
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
  // Colour space (docs/DESIGN.md §9), first that applies: the command line; the file's own
  // metadata (a file rule that agrees refines it; one naming a data space wins; one that
  // disagrees is named in a warning); the config's file rules; the format's convention; the
  // config's role for the data type.
  if (!settings.colorspace.empty()) {
    in.colorspace = settings.colorspace;  // resolved by the planner (pipeline/job_plan.h)
    in.colorspace_reason =
        settings.colorspace_given_by.empty() ? "--colorspace" : settings.colorspace_given_by;
    // What the file says of itself, where it disagrees: named, the given space followed.
    std::vector<std::string> unheard;  // its tags' own troubles: not this decision's
    if (const Stated meta = metadata_space(file, spec, spaces, in.colorspace, unheard);
        meta && !agrees(spaces, in.colorspace, meta) &&
        !(meta.primaries_only && spaces.facts(in.colorspace).data)) {
      in.contradiction = "its " + meta.reason + " says '" + meta.space + "', but " +
                         in.colorspace_reason + " says '" + in.colorspace + "': '" + in.colorspace +
                         "' is followed";
      in.warnings.push_back(where + in.contradiction);
    }
  } else {
    const auto [ruled, rule] = spaces.file_rule(file);
    std::pair<std::string, std::string> role;
    std::string role_error;
    try {
      role = default_colour_space(spaces, float_data);
    } catch (const Error& e) {
      role_error = e.what();
    }
    std::vector<std::string> convention_warnings;
    const Stated convention = ruled.empty()
                                  ? format_convention(file, float_data, spaces, convention_warnings,
                                                      role.first.empty() ? "?" : role.first)
                                  : Stated{};
    const std::string fallback = !ruled.empty()       ? ruled
                                 : convention         ? convention.space
                                 : role.first.empty() ? std::string("?")
                                                      : role.first;
    const Stated meta = metadata_space(file, spec, spaces, fallback, in.warnings);
    const std::string rule_reason = "the config's file rule '" + rule + "'";
    if (meta && !ruled.empty() && spaces.facts(ruled).data) {
      // Tools tag data maps sRGB as readily as colour: the rule is the studio's word.
      in.colorspace = ruled;
      in.colorspace_reason = rule_reason + " (a data space; the file's own tag, '" + meta.space +
                             "', describes an encoding only)";
    } else if (meta && !ruled.empty() && agrees(spaces, ruled, meta)) {
      in.colorspace = meta.primaries_only ? ruled : meta.space;
      in.colorspace_reason = meta.primaries_only
                                 ? rule_reason + " (agrees with its " + meta.reason + ")"
                                 : meta.reason + " (" + rule_reason + " agrees)";
    } else if (meta) {
      if (!ruled.empty())
        in.warnings.push_back(where + rule_reason + " says '" + ruled + "', but its " +
                              meta.reason +
                              ": the file's own statement is followed (give "
                              "--colorspace to choose)");
      in.colorspace = meta.space;
      in.colorspace_reason = meta.reason;
    } else if (!ruled.empty()) {
      in.colorspace = ruled;
      in.colorspace_reason = rule_reason;
    } else if (convention) {
      in.colorspace = convention.space;
      in.colorspace_reason = convention.reason;
    } else {
      for (const std::string& w : convention_warnings) in.warnings.push_back(w);
      if (!role_error.empty()) throw ConfigError(role_error);
      in.colorspace = role.first;
      in.colorspace_reason =
          (float_data ? "default for floating-point data: " : "default for integer data: ") +
          role.second;
    }
  }
  // Everything known of the space decided, passed on whole; one no colour converts through
  // fails this file before any pixel is read.
  in.facts = &spaces.facts(in.colorspace);
  if (!in.facts->unusable.empty())
    throw Error(where + "colour space '" + in.colorspace + "' (" + in.colorspace_reason +
                ") cannot be used: " + in.facts->unusable);
  // Data or colour: the words of the name and its folders, then a data colour space.
  if (!settings.stated_for_file)
    in.name =
        map_kind_by_name(file, name_words_in_force(settings.data_names, settings.colour_names));
  resolve_by_channels(in.name, in.channels.grey());
  for (const std::string& w : in.name.warnings) in.warnings.push_back(where + w);
  if (in.name.kind == MapKind::data)
    in.data_reason = "data by its " + in.name.reason;
  else if (in.facts->data)
    in.data_reason = "colour space '" + in.colorspace + "' is data (" + in.colorspace_reason + ")";
  return in;
}

std::string data_space_warning(const std::string& space) {
  return "colour space '" + space +
         "' is marked as data (not colour) in the OCIO config; its values are taken as CIE XYZ";
}

InputInterpretation interpret_input(const std::string& file, const OIIO::ImageSpec& spec,
                                    const Settings& settings, const ColourSpaces& spaces) {
  InputInterpretation in = interpret_colour(file, spec, settings, spaces);
  const std::string where = "'" + clip(file, 200) + "': ";
  if (in.facts->data)
    in.warnings.push_back(where + data_space_warning(in.colorspace));
  else if (!in.data_reason.empty())
    in.warnings.push_back(where + "non-colour data by its " + in.name.reason +
                          ": its values are not a colour; converted as asked (ingest skips "
                          "such files)");
  decide_light_or_surface(in, file, spec, settings, spaces);
  return in;
}

void decide_light_or_surface(InputInterpretation& in, const std::string& file,
                             const OIIO::ImageSpec& spec, const Settings& settings,
                             const ColourSpaces& spaces) {
  const std::string where = "'" + clip(file, 200) + "': ";
  // Light or surface (docs/DESIGN.md §9).
  ModeClues clues;
  clues.asked = settings.mode;
  clues.asked_by = settings.mode_given_by;
  clues.name = in.name;
  clues.float_data = spec.format.is_floating_point();
  clues.colorspace = in.colorspace;
  clues.width = spec.width;
  clues.height = spec.height;
  clues.recorded_mode = spec.get_string_attribute("spectralize:mode");
  clues.can_exceed_white = clues.float_data || in.facts->white.Y > kLightAboveY;
  clues.brightest = [&] {
    return brightest_pixel(file, in.channels, spaces.to_xyz(in.colorspace), kClearlyLightY);
  };
  const ModeDecision d = decide_mode(clues);
  in.mode = d.mode;
  in.mode_reason = d.reason;
  for (const std::string& w : d.warnings) in.warnings.push_back(where + w);
}

Settings resolved_settings(const Settings& settings, const InputInterpretation& in,
                           const ColourSpaces& spaces) {
  Settings s = settings;
  s.spectral.mode = in.mode;
  s.colorspace = in.colorspace;
  s.preview_colorspace = settings.preview_colorspace.empty()
                             ? default_colour_space(spaces, true).first
                             : settings.preview_colorspace;
  return s;
}

}  // namespace spectralize
