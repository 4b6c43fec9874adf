#pragma once
// Every setting of spectralize, declared once (docs/DESIGN.md §8): its command-line flag, its
// recipe key, the commands it applies to, its validation, its canonical text and its help. The
// CLI, the recipes of the OpenImageIO plugin, the reports, the EXR attributes, the --color JSON,
// plot titles and the node cache's key are all generated from this one table, so they cannot
// drift apart. Defaults are the member initialisers of Settings (and of SpectralizerSettings).

#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/tables/spectral_table.h"
#include "spectralize/core/spectralizer.h"

namespace spectralize {

/// The commands of spectralize, as bits: a setting lists those it applies to.
enum Command : unsigned {
  kImage = 1u << 0,      // INPUT -o OUTPUT.exr (and "to": "spectral" recipes)
  kToRgb = 1u << 1,      // --to-rgb IN.exr -o OUT (and "to": "rgb" recipes)
  kColor = 1u << 2,      // --color R,G,B (printed)
  kPlotColor = 1u << 3,  // --color R,G,B -o PLOT
  kPlotPixel = 1u << 4,  // --plot-pixel X,Y IN.exr -o PLOT
  kIngest = 1u << 5,     // ingest SRC... -o DESTDIR
  kTable = 1u << 6,      // table -o NAME.spztab (a render-time table, pipeline/render_table.h)
};

/// A command as --help, messages and `--help-markdown-for` name it: the word or flag a user
/// types ("image", "--to-rgb", "plot": a --color with -o PLOT); its guide page is the name
/// without the leading "--".
struct CommandName {
  Command bit;
  std::string_view name;
  /// The name without a leading "--" ("to-rgb"). Cost: O(1).
  std::string_view page() const { return name.rfind("--", 0) == 0 ? name.substr(2) : name; }
};

/// Every command, in --help's order. Cost: O(1).
std::span<const CommandName> command_names();

/// How the mode is chosen.
enum class ModeChoice { automatic, emission, reflectance };

/// Every option of every command, with its default.
/// How --plot draws values.
enum class PlotScale { linear, log, normalized };

/// What `ingest` does per file beyond the single-file settings (ingest/ingest.h).
struct IngestSettings {
  std::string name_pattern = "{dir}/{stem}.exr";  // output path under the destination
  bool copy_data = false;  // copy non-colour files unchanged (else skip them)
  int jobs = 0;            // files converted at once (0: from the cores)
};

struct Settings {
  // What the input is (for --to-rgb: what the output is).
  std::string colorspace;  // "" : from the file / the config (see input_interpretation.h)
  ModeChoice mode = ModeChoice::automatic;
  SpectralizerSettings spectral;  // grid, observer, illuminant, filter, model, basis, tau
  // How it is written.
  bool half = true;                 // HALF (else FLOAT) samples
  int integer_bits = 0;             // --to-rgb into PNG, TIFF...: 8 or 16-bit samples (0: float)
  bool json = false;                // --color prints JSON (else CSV)
  std::string compression = "zip";  // OpenEXR compression, OIIO's "name[:level]"
  int tile_width = 0, tile_height = 0;  // 0: scanlines; else tiles of this size
  std::string preview_colorspace;       // "" : the config's scene_linear role
  bool as_lit = false;                  // --to-rgb: reflected light as lit (else white balanced)
  std::string display, view;            // --to-rgb: an OCIO display and view instead of a space
  PlotScale plot_scale = PlotScale::linear;
  SpectralTable::Method method = SpectralTable::Method::table;
  std::string cache_dir;   // "" : no persistent node cache
  int threads = 0;         // 0: all cores
  std::string config;      // OCIO config file ("" : $OCIO, else the shipped one)
  std::string rgb_to_xyz;  // table: a renderer's RGB -> XYZ, canonical (core/renderer_frame.h)
  // Edits of the name table (settings/map_kind.h), canonical: "" (the table), a replacing list
  // ("normal,rough") or signed words ("+msk,-metal"; colour words may end in ":emission").
  std::string data_names, colour_names;
  IngestSettings ingest;
  // The settings the user gave (a flag, a keyword, a recipe key), by their place in the
  // schema: what may be refused as unable to shape the output (ineffective_setting).
  std::uint64_t given = 0;
  // Who gave the colour space and mode when a list line's origin says ("" : the option
  // itself, "--colorspace"): the reasons decisions record, e.g. a USD stage's declaration.
  std::string colorspace_given_by, mode_given_by;
  // A list line states this file's colour space or mode: the words of its name do not make
  // it data (what it is was said for it alone).
  bool stated_for_file = false;
};

/// One setting of the schema.
struct SettingSpec {
  std::string_view key;        // recipe key and report/JSON key, e.g. "emission_basis"
  std::string_view flag;       // command-line flag, e.g. "--emission-basis"
  std::string_view metavar;    // its value in --help, e.g. "NAME"
  std::string_view attribute;  // EXR attribute (after "spectralize:"), "" if not written
  std::string help;            // one sentence, without the default
  unsigned commands = 0;       // Command bits it applies to
  bool recipe = true;          // accepted in .spectral recipes
  bool spectral = false;       // node spectra depend on it: part of the cache key
  /// Validates `text` and stores it; throws Error (the message does not name the flag).
  std::function<void(Settings&, std::string_view text)> parse;
  /// The canonical text of the current value, parseable by parse().
  std::function<std::string(const Settings&)> format;
  /// Whether the value matters for these settings (e.g. the filter only for the paper model,
  /// the illuminant only for reflectances); nullptr: always.
  std::function<bool(const Settings&)> relevant;
  std::string_view default_text{};  // --help's default when format(Settings{}) does not say it
  std::string_view alias{};         // a second flag, in the OIIO tools' spelling (e.g. "-d")
  // The written spectral file depends on it (when it matters): recorded in the header and part
  // of ingest's up-to-date key. False only for how a job runs (threads, cache, jobs), where
  // its outputs go, and the config (which enters the key by its content). A new setting
  // shapes the file unless it says otherwise: at worst a needless conversion, never a stale
  // file kept.
  bool shapes_file = true;

  /// True when it applies to `command`. Cost: O(1).
  bool applies(Command command) const { return (commands & command) != 0; }
  /// True when relevant() says so (or there is no predicate). Cost: O(1).
  bool matters(const Settings& s) const { return !relevant || relevant(s); }
};

/// The schema, in --help order. Cost: O(1) after the first call.
const std::vector<SettingSpec>& settings_schema();

/// The setting with recipe key `key`, or nullptr. Cost: O(settings).
const SettingSpec* find_setting(std::string_view key);

/// The setting a command-line flag (or its alias) means for `command`, or nullptr (an unknown
/// flag, or one that does not apply; see flag_commands). Cost: O(settings).
const SettingSpec* find_setting_for_flag(std::string_view flag, Command command);

/// The commands any setting with this flag applies to (0: not a setting's flag). Cost:
/// O(settings).
unsigned flag_commands(std::string_view flag);

/// Validates and stores a value given as text, for messages named `where` (the flag or the
/// recipe key): throws Error "<where> '<value>': <why>". An empty value is always refused.
/// Cost: the setting's parse.
void apply_setting(Settings& settings, const SettingSpec& spec, std::string_view text,
                   std::string_view where);

/// True when the user gave `spec` (apply_setting stored it). Cost: O(1).
bool was_given(const Settings& settings, const SettingSpec& spec);

/// Takes `spec` out of what the user gave, for a front end that sets the value aside itself (a
/// reader that must not create a cache folder drops it). Cost: O(1).
void set_aside(Settings& settings, const SettingSpec& spec);

/// The first setting the user gave that cannot shape the output for these settings: for the
/// mode `decided`, or, when each input decides its own (an image's "auto"), in neither mode; so
/// a flag the model ignores (--filter but for the paper model), --emission-basis on
/// reflectances, --illuminant on light. nullptr when each can. Every front end refuses such a
/// setting the same way (pipeline/job_plan.h). Cost: O(settings).
const SettingSpec* ineffective_setting(const Settings& settings, std::optional<Mode> decided);

/// The canonical text of a setting's value as done: format(), except that "mode" is the mode
/// resolved into settings.spectral.mode (never "auto"). Cost: the setting's format.
std::string setting_value(const SettingSpec& spec, const Settings& settings);

/// The canonical text of every setting that applies to `command` and matters for `settings`
/// (key, value), in schema order. `spectral_only`: only those the spectra depend on.
/// Cost: O(settings).
std::vector<std::pair<std::string, std::string>> describe_settings(const Settings& settings,
                                                                   Command command,
                                                                   bool spectral_only = false);

/// The settings that shape a written spectral file, as resolved for it (mode resolved in
/// settings.spectral.mode; colorspace and preview_colorspace the spaces decided for the file):
/// those that shape files, apply to the image job and matter for these settings, in schema
/// order (spec, canonical value). What the file's header records and what ingest's up-to-date
/// key hashes, so the two cannot drift apart. Cost: O(settings).
std::vector<std::pair<const SettingSpec*, std::string>> file_settings(const Settings& resolved);

/// Everything the node spectra of a table depend on, as text: the version, the spectral
/// settings that matter (mode resolved in settings.spectral.mode) and the table's node layout.
/// Cost: O(settings).
std::string table_cache_key(const Settings& settings, const std::string& table_layout);

/// "emission" / "reflectance" / "auto". Cost: O(1).
std::string_view to_string(ModeChoice mode);

/// "linear" / "log" / "normalized". Cost: O(1).
std::string_view to_string(PlotScale scale);

}  // namespace spectralize
