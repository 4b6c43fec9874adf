#pragma once
// Colour spaces by name, converted to CIE XYZ (D65) through an OpenColorIO config. The OCIO
// headers stay in colour_space.cpp; callers see only names and float RGB.

#include <array>
#include <initializer_list>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "colour/icc_profile.h"
#include "colour/known_spaces.h"
#include "core/colorimetry/mat3.h"
#include "spectralize/core/xyz.h"

namespace spectralize {

/// A conversion between two colour spaces by OCIO (in float). Copyable, thread-safe to apply.
class ColourTransform {
 public:
  /// Converts `pixels` packed triples in place. Cost: O(pixels).
  void apply(float* rgb, std::size_t pixels) const;
  /// Converts one colour. Cost: O(1) plus OCIO overhead.
  Xyz operator()(double r, double g, double b) const;
  /// Canonical name of the colour space on the RGB side. Cost: O(1).
  const std::string& source() const { return source_; }

 private:
  friend class ColourSpaces;
  std::shared_ptr<const void> processor_;  // OCIO::ConstCPUProcessorRcPtr, type-erased
  std::string source_;
};

struct ColourFactsCache;  // colour_space.cpp

/// What is known of one colour space of a config (docs/DESIGN.md §9), gathered once per space:
/// what the config states (OCIO 2.5's interop ID, the encoding, data, its reference space) and
/// what one OCIO processor to CIE XYZ measures (linearity, primaries and white, the transfer).
struct ColourSpaceFacts {
  std::string name;                     // canonical
  std::string interop_id;               // "lin_ap1_scene", "data", ..., or "" when none is known
  bool interop_id_from_config = false;  // stated by the config (OCIO 2.5); else measured
  std::string encoding;                 // the config's: "scene-linear", "sdr-video", "log", ...
  bool data = false;                    // not colour: the config's isdata, a "data" encoding or ID
  bool display_referred = false;        // defined by the config's display reference space
  // Measured through one OCIO processor to CIE XYZ (D65):
  Xyz white;                       // what RGB (1, 1, 1) is
  std::optional<Mat3> rgb_to_xyz;  // the unit colours as columns, when finite and invertible
  bool linear = false;  // the conversion is rgb_to_xyz, inside [0, 1] and out (the one test)
  // Red, green, blue and white as CIE xy, as XYZ-D65 sees them (the white adapted to D65):
  // measured along each primary's direction, so any per-channel curve (sRGB, log) keeps them.
  std::optional<std::array<float, 8>> primaries_d65;
  // What a file's chromaticities attribute says: a known standard's own primaries and white
  // (ACEScg: the ACES white), else primaries_d65.
  std::optional<std::array<float, 8>> chromaticities;
  std::optional<IccTransfer> transfer;  // linear, the sRGB curve or a pure gamma, if one
  // Why no colour can be converted through the space ("" when one can): its conversion to CIE
  // XYZ gives NaN or infinity, the same XYZ for every colour, or is singular (docs/DESIGN.md §9).
  std::string unusable;
};

/// A colour space a user named (an option or a keyword), resolved once: the name as given and
/// everything known of the space. The planner makes it (pipeline/job_plan.h); the classifier,
/// the converters and the writers take it whole.
struct NamedSpace {
  std::string given;                        // as typed ("": none given)
  const ColourSpaceFacts* facts = nullptr;  // owned by the ColourSpaces that resolved it
  /// The canonical name. Cost: O(1).
  const std::string& name() const { return facts->name; }
  /// True when a space was named. Cost: O(1).
  explicit operator bool() const { return facts != nullptr; }
};

class ColourSpaces {
 public:
  /// Loads the config: `explicit_path` if non-empty, else $OCIO if set, else the config shipped
  /// with spectralize (embedded). A file must be a regular file (a FIFO would block); an
  /// `ocio://` URI names one of OCIO's built-in configs (OCIO 2.2 and later; refused naming the
  /// version before). Throws Error naming the file and OCIO's reason. Cost: reading the file; the
  /// parse (~ms) only the first time the process meets these bytes at this location.
  static ColourSpaces load(const std::string& explicit_path = "");

  /// The OpenColorIO in use ("2.5.1"). Cost: O(1).
  static std::string ocio_version();

  /// Where the config came from, for reports: "shipped", "$OCIO=path" or the path (or URI).
  /// Cost: O(1).
  const std::string& origin() const { return origin_; }
  /// What a built-in URI resolved to ("ocio://cg-config-v4.0.0_aces-v2.0_ocio-v2.5"), or "" for
  /// a config file or the shipped one. Cost: O(1).
  const std::string& builtin() const { return builtin_; }
  /// True for the config shipped with spectralize. Cost: O(1).
  bool shipped() const { return origin_ == "shipped"; }
  /// The files the config's transforms read (FileTransform LUTs: as written, and where the
  /// config's search path finds them, "" when it does not). Cost: a walk of every transform.
  std::vector<std::pair<std::string, std::string>> referenced_files() const;
  /// What the config is, by content: a hash of the config file's bytes and of every file its
  /// transforms read, so that one config reached by a relative path, an absolute path or a link
  /// (or copied to another machine) is the same config. Cost: reading those files.
  std::string content_identity() const;
  /// The canonical name of the space a role names, or "" when the config has no such role.
  /// Cost: O(1).
  std::string role(std::string_view role) const;
  /// The canonical name of the space of the first of `roles` the config has, else of the first
  /// of `names` (the shipped config's, for configs without those roles) it knows; throws
  /// ConfigError naming the config, the missing roles and `purpose`. Cost: O(roles + names).
  std::string role_or_name(std::initializer_list<std::string_view> roles,
                           std::initializer_list<std::string_view> names,
                           std::string_view purpose) const;
  /// The space the config's file rules give `path` and the rule's name, or {"", ""} when only
  /// the default rule matches. Cost: O(rules).
  std::pair<std::string, std::string> file_rule(const std::string& path) const;
  /// `given` (a name, alias or role) resolved with what is known of it; an empty NamedSpace
  /// for "". Throws Error listing the valid names, or as usable() for a space no colour can be
  /// converted through. Cost: facts().
  NamedSpace named(std::string_view given) const;
  /// The facts of a space colours can be converted through: throws Error "colour space 'NAME'
  /// cannot be used: REASON" when facts().unusable says why not (never for data, whose values
  /// are taken as they are). Cost: facts().
  const ColourSpaceFacts& usable(std::string_view space) const;
  /// Everything known of a space (by name, alias or role), gathered the first time any copy of
  /// this ColourSpaces asks; the reference stays valid while one does. Throws Error for an
  /// unknown space. Cost: one OCIO processor and ~20 colours the first time, O(log spaces) after.
  const ColourSpaceFacts& facts(std::string_view space) const;
  /// True when the space is data, not colour (facts().data); false for an unknown name.
  /// Cost: facts().
  bool is_data(std::string_view space) const;
  /// True when the space's conversion to XYZ is linear (facts().linear). Cost: facts().
  bool is_linear(std::string_view space) const;
  /// What an OpenEXR `chromaticities` attribute says of the space (facts().chromaticities);
  /// nullopt for data. Cost: facts().
  std::optional<std::array<float, 8>> chromaticities(std::string_view space) const;
  /// The space's transfer function when an ICC profile states it exactly: linear, the sRGB curve
  /// or a pure gamma (2.2, 563/256, 2.4, 1.8, 2.6), measured on greys; nullopt otherwise (log,
  /// PQ, data). Cost: facts().
  std::optional<IccTransfer> transfer(std::string_view space) const;
  /// The colour interop ID (e.g. "lin_ap1_scene"): the config's own (OCIO 2.5), else measured
  /// for a space whose primaries, white and encoding match a known one ("<curve>_<primaries>_
  /// scene", "..._display" for a display-referred space, "data"), else "". Cost: facts().
  std::string interop_id(std::string_view space) const;
  /// True when the config defines the space by its display reference (the output of a
  /// display's view, e.g. ACES configs' "sRGB - Display"). Cost: facts().
  bool is_display_referred(std::string_view space) const;
  /// The primaries and white as CIE xy as XYZ-D65 sees them (facts().primaries_d65), what a
  /// file's adapted chromaticities are compared with; nullopt for data or a space without RGB
  /// primaries. Cost: facts().
  std::optional<std::array<float, 8>> primaries_d65(std::string_view space) const;
  /// The linear, scene-referred space of the config with the primaries and white of `space`:
  /// `space` itself when it is linear; else the space whose interop ID is "lin_<its primaries>_
  /// scene"; else one whose measured primaries and white agree within 2e-4; "" when none is.
  /// Cost: facts() of every space the first time.
  std::string linear_twin(std::string_view space) const;
  /// The canonical name of a colour space given by name, alias or role (case-insensitive), or
  /// by a Color Interop Forum ID no space is named ("lin_ap1_scene", as OpenUSD and OIIO 3 name
  /// spaces: space_of_interop_id); throws Error listing the valid names. Cost: O(spaces); an
  /// interop ID, the facts of the spaces tried.
  std::string resolve(std::string_view name) const;
  /// The space whose interop ID (stated or measured) is `id`: the first of `preferred` with it,
  /// then the config's roles, the names configs usually give it (known_spaces.h), then any
  /// space (so that an alias meaning something else in a studio config is not taken, and
  /// "sRGB - Texture" is not read as "sRGB - Display"); "" when none has it. Cost: the facts
  /// of the spaces tried.
  std::string space_of_interop_id(std::string_view id,
                                  const std::vector<std::string>& preferred = {}) const;
  /// Every colour-space name (canonical). Cost: O(spaces).
  std::vector<std::string> names() const;
  /// Every colour-space name with its aliases, "Name (alias1, alias2)". Cost: O(spaces).
  std::vector<std::string> describe() const;
  /// A converter from `space` to CIE-XYZ-D65: to the config's XYZ space (the
  /// cie_xyz_d65_interchange role, or a space of a known name), else to its ACES2065-1 space and
  /// on by OCIO's built-in Bradford transform (classic v1 ACES configs); throws Error for unknown
  /// spaces or configs without any of them, and as usable() for a space no colour can be
  /// converted through. Cost: OCIO processor build, ~ms (cached by OCIO).
  ColourTransform to_xyz(std::string_view space) const;
  /// A converter from CIE-XYZ-D65 to `space`; throws Error as to_xyz. Cost: as to_xyz.
  ColourTransform from_xyz(std::string_view space) const;
  /// A converter from CIE-XYZ-D65 to an OCIO display and view (the display's default view when
  /// `view` is empty); throws Error naming the valid displays or views. Cost: as to_xyz.
  ColourTransform display_from_xyz(const std::string& display, const std::string& view) const;
  /// The colour space a display's view ends in (to tag files), or "" if the config does not
  /// name one. Cost: O(1).
  std::string display_colour_space(const std::string& display, const std::string& view) const;

 private:
  // The conversion as OCIO makes it, unchecked (gather_facts measures it).
  ColourTransform transform(std::string_view space, bool to_xyz) const;
  ColourSpaceFacts gather_facts(const std::string& space) const;
  std::shared_ptr<const void> config_;       // OCIO::ConstConfigRcPtr, type-erased
  std::shared_ptr<ColourFactsCache> facts_;  // shared by every load of the same config
  std::string origin_;
  std::string file_;     // the config file ("": the shipped one or a built-in)
  std::string builtin_;  // a built-in config's resolved URI ("": a file or the shipped one)
};

/// Name of the shipped default linear space (scene_linear of the shipped config). Cost: O(1).
inline constexpr std::string_view kDefaultColourSpace = "Linear Rec.709 (sRGB)";

}  // namespace spectralize
