#include "colour/colour_space.h"

#include <OpenColorIO/OpenColorIO.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <sstream>

#include "colour/file_rule_screen.h"
#include "colour/ocio_compat.h"
#include "core/work_counts.h"
#include "imagefile/safe_output.h"
#include "spectralize/core/error.h"
#include "text/strings.h"

namespace OCIO = OCIO_NAMESPACE;

namespace spectralize {

namespace embedded {
extern const std::string_view kOcioConfig;
}

// Every space's facts, gathered once (ColourSpaces::facts): entries are never removed, so a
// reference to one stays valid while the cache lives.
struct ColourFactsCache {
  std::mutex mutex;
  std::map<std::string, std::unique_ptr<const ColourSpaceFacts>, std::less<>> by_name;
  std::optional<FileRuleScreen> file_rules;  // set once, when the config is parsed
};

namespace {

using ConfigPtr = OCIO::ConstConfigRcPtr;
using CpuPtr = OCIO::ConstCPUProcessorRcPtr;

const ConfigPtr& config_of(const std::shared_ptr<const void>& p) {
  return *static_cast<const ConfigPtr*>(p.get());
}

// How a config reaches CIE XYZ (D65): its XYZ space, or, for configs without one (classic
// OCIO v1 ACES configs), its ACES2065-1 space followed by OCIO's built-in Bradford transform.
struct XyzRoute {
  std::string space;     // the config's space to convert to (or from)
  bool via_ap0 = false;  // then OCIO's built-in AP0 -> XYZ-D65 (Bradford)
};

// The names a CIE-XYZ-D65 space, or an ACES2065-1 space (role first), goes by in known configs.
constexpr const char* kXyzNames[] = {"CIE-XYZ-D65", "CIE XYZ-D65 - Scene-referred", "cie_xyz_d65"};
constexpr const char* kAp0Names[] = {"aces_interchange", "ACES2065-1", "ACES - ACES2065-1",
                                     "aces2065_1", "lin_ap0"};

XyzRoute xyz_route_of(const ConfigPtr& config, const std::string& origin) {
  if (config->hasRole("cie_xyz_d65_interchange")) {
    auto cs = config->getColorSpace("cie_xyz_d65_interchange");
    if (cs) return {cs->getName(), false};
  }
  for (const char* name : kXyzNames) {
    auto cs = config->getColorSpace(name);
    if (cs) return {cs->getName(), false};
  }
  // Derived from the config's ACES2065-1 space where it has one (OCIO knows AP0 exactly).
  for (const char* name : kAp0Names) {
    auto cs = config->getColorSpace(name);
    if (cs && !cs->isData()) return {cs->getName(), true};
  }
  std::string xyz, ap0;
  for (const char* name : kXyzNames) xyz += (xyz.empty() ? "'" : ", '") + std::string(name) + "'";
  for (const char* name : kAp0Names)
    if (std::string_view(name) != "aces_interchange")
      ap0 += (ap0.empty() ? "'" : ", '") + std::string(name) + "'";
  throw ConfigError("the OCIO config '" + origin +
                    "' has no route to CIE XYZ (D65): it lacks the roles "
                    "cie_xyz_d65_interchange and aces_interchange and has no colour space named " +
                    xyz + " (CIE XYZ) or " + ap0 +
                    " (ACES2065-1); add one of these roles or spaces to the config");
}

bool is_builtin_uri(std::string_view path) {
  return path.rfind("ocio://", 0) == 0;
}

// Parsing a config compiles its file rules into regular expressions (milliseconds, and a
// recursion deep enough to matter under a recipe chain): a job, a chain of recipes and a batch
// read the same config many times, so a process keeps what it parsed, keyed by the config's
// location and bytes (an edited file is parsed again; a built-in URI is its own key). Parsed
// configs are immutable and OCIO reads them from any thread. `path` empty: the shipped config.
// `resolved` is what a built-in URI resolved to ("ocio://cg-config-v4.0.0_aces-v2.0_ocio-v2.5");
// `facts` the config's colour-space facts, gathered by whichever load asks first.
struct Parsed {
  ConfigPtr config;
  std::string resolved;
  std::shared_ptr<ColourFactsCache> facts;
};

// The config's file rules as the screen reads them.
std::vector<FileRuleText> file_rule_texts(const OCIO::Config& config) {
  const OCIO::ConstFileRulesRcPtr rules = config.getFileRules();
  std::vector<FileRuleText> out;
  for (std::size_t i = 0; i < rules->getNumEntries(); ++i) {
    FileRuleText r;
    if (i + 1 == rules->getNumEntries())
      r.kind = FileRuleText::Kind::fallback;  // OCIO keeps the default rule last
    else if (const char* pattern = rules->getPattern(i); pattern && *pattern)
      r.pattern = pattern, r.extension = rules->getExtension(i);
    else
      r.kind = FileRuleText::Kind::other;
    out.push_back(std::move(r));
  }
  return out;
}

Parsed parsed_config(const std::string& path) {
  static std::mutex mutex;
  static std::map<std::string, Parsed> parsed;
  std::string key = "shipped";
  if (is_builtin_uri(path)) {
    key = path;
  } else if (!path.empty()) {
    std::ifstream f(path, std::ios::binary);
    std::ostringstream bytes;
    bytes << f.rdbuf();
    std::error_code ec;
    const std::filesystem::path where = std::filesystem::absolute(path, ec);
    key = (ec ? path : where.string()) + '\0' + bytes.str();
  }
  {
    std::lock_guard<std::mutex> lock(mutex);
    if (auto it = parsed.find(key); it != parsed.end()) return it->second;
  }
  Parsed p;
  count_work(Work::config_parsed);
  if (path.empty()) {
    std::istringstream text{std::string(embedded::kOcioConfig)};
    p.config = OCIO::Config::CreateFromStream(text);
  } else if (is_builtin_uri(path)) {
    p.config = ocio_compat::builtin_config(path, p.resolved);
  } else {
    p.config = OCIO::Config::CreateFromFile(path.c_str());
  }
  p.config->validate();
  p.facts = std::make_shared<ColourFactsCache>();
  p.facts->file_rules.emplace(file_rule_texts(*p.config));
  std::lock_guard<std::mutex> lock(mutex);
  if (parsed.size() >= 16) parsed.clear();  // a bound, for processes that see many configs
  return parsed.emplace(std::move(key), std::move(p)).first->second;
}

// Exactness is promised through OCIO (docs/DESIGN.md §3): its processors are asked for lossless
// optimisation only. The default (OPTIMIZATION_VERY_GOOD) lets OCIO 2.2+ use fast approximate
// pow/log/exp (OPTIMIZATION_FAST_LOG_EXP_POW, SIMD) and composed 1D LUTs: an sRGB 0.5 then
// reaches XYZ 4.7e-6 off with OCIO 2.5.
CpuPtr exact_cpu_processor(const OCIO::ConstProcessorRcPtr& processor) {
  return processor->getOptimizedCPUProcessor(OCIO::BIT_DEPTH_F32, OCIO::BIT_DEPTH_F32,
                                             OCIO::OPTIMIZATION_LOSSLESS);
}

// Why no colour can be converted through a space whose conversion to CIE XYZ is `t`, or "":
// NaN or infinity at white, at mid grey or along a primary's direction from it; or, from each
// of three greys (0.5, 0.1, 0.02: a curve may saturate at some, as ADX16's does above 0.5),
// every direction zero (every colour the same XYZ; a zero matrix: all black) or the three not
// independent (a singular matrix: different colours meet; their volume below 1e-6 of the
// product of their lengths, whatever the scale).
std::string unusable_reason(const ColourTransform& t) {
  auto text = [](const Xyz& c) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "(%.4g, %.4g, %.4g)", c.X, c.Y, c.Z);
    return std::string(buf);
  };
  const Xyz white = t(1, 1, 1), mid = t(0.5, 0.5, 0.5);
  const char* why_nan = "its conversion to CIE XYZ gives NaN or infinity (RGB ";
  if (!white.finite()) return why_nan + std::string("(1, 1, 1) -> XYZ ") + text(white) + ")";
  if (!mid.finite()) return why_nan + std::string("(0.5, 0.5, 0.5) -> XYZ ") + text(mid) + ")";
  bool constant = true;
  for (const double g : {0.5, 0.1, 0.02}) {
    const Xyz base = t(g, g, g);
    const Xyz dirs[3] = {t(2 * g, g, g) - base, t(g, 2 * g, g) - base, t(g, g, 2 * g) - base};
    double length = 1;
    for (int k = 0; k < 3; ++k) {
      if (!dirs[k].finite())
        return "its conversion to CIE XYZ gives NaN or infinity (more " +
               std::string(k == 0   ? "red"
                           : k == 1 ? "green"
                                    : "blue") +
               " than the grey " + std::to_string(g).substr(0, 4) + ")";
      length *= std::sqrt(dot(dirs[k], dirs[k]));
      constant = constant && dirs[k].max_abs() == 0;
    }
    if (std::abs(dot(dirs[0], cross(dirs[1], dirs[2]))) > 1e-6 * length) return "";
  }
  if (constant)
    return white.max_abs() == 0
               ? "its conversion to CIE XYZ makes every colour black (XYZ 0)"
               : "its conversion to CIE XYZ gives every colour the same XYZ " + text(white);
  return "its conversion to CIE XYZ is singular: its primaries are not independent, so "
         "different colours become the same XYZ";
}

}  // namespace

void ColourTransform::apply(float* rgb, std::size_t pixels) const {
  const CpuPtr& cpu = *static_cast<const CpuPtr*>(processor_.get());
  OCIO::PackedImageDesc desc(rgb, static_cast<long>(pixels), 1, 3);
  cpu->apply(desc);
}

Xyz ColourTransform::operator()(double r, double g, double b) const {
  float px[3] = {static_cast<float>(r), static_cast<float>(g), static_cast<float>(b)};
  const CpuPtr& cpu = *static_cast<const CpuPtr*>(processor_.get());
  cpu->applyRGB(px);
  return {px[0], px[1], px[2]};
}

std::string ColourSpaces::ocio_version() {
  return OCIO::GetVersion();
}

ColourSpaces ColourSpaces::load(const std::string& explicit_path) {
  // OCIO logs its own opinions of a config (inactive spaces, deprecated keys) on stderr;
  // spectralize reports what matters to the job itself, naming the config.
  static const bool quiet = [] {
    OCIO::SetLoggingLevel(OCIO::LOGGING_LEVEL_NONE);
    return true;
  }();
  (void)quiet;
  ColourSpaces cs;
  ConfigPtr config;
  std::string where;
  const char* env = std::getenv("OCIO");
  const std::string source = !explicit_path.empty() ? explicit_path : env && *env ? env : "";
  // A built-in config this OCIO does not have: a mistake of the command line (or of $OCIO).
  if (is_builtin_uri(source) && !ocio_compat::kBuiltinConfigs) {
    const std::string why =
        "built-in configs (ocio://...) need OpenColorIO 2.2 or later; this "
        "build uses OpenColorIO " +
        std::string(OCIO::GetVersion()) + ": give the path of a config file";
    // A config that cannot be loaded, however it was named (exit 1, docs/guide/files.md).
    throw ConfigError(std::string("OCIO config '") + (explicit_path.empty() ? "$OCIO=" : "") +
                      source + "': " + why);
  }
  try {
    if (!explicit_path.empty()) {
      where = explicit_path;
      cs.origin_ = explicit_path;
    } else if (!source.empty()) {
      where = "$OCIO=" + source;
      cs.origin_ = where;
    } else {
      where = "the shipped config";
      cs.origin_ = "shipped";
    }
    if (!source.empty() && !is_builtin_uri(source))
      check_readable_file(source, explicit_path.empty() ? "$OCIO" : "OCIO config");
    const Parsed p = parsed_config(source);
    config = p.config;
    cs.builtin_ = p.resolved;
    cs.facts_ = p.facts;
    cs.file_ = is_builtin_uri(source) ? "" : source;
  } catch (const OCIO::Exception& e) {
    throw ConfigError("OCIO config '" + where + "': " + clip(e.what(), 300));
  } catch (const Error& e) {  // not a readable regular file
    const std::string why = e.what();
    const std::size_t at = why.find("): ");
    throw ConfigError("OCIO config '" + where +
                      "': " + (at == std::string::npos ? why : why.substr(at + 3)));
  }
  cs.config_ = std::make_shared<const ConfigPtr>(config);
  // What its transforms read is read by the run too: never an output of it.
  for (const auto& [src, resolved] : cs.referenced_files())
    if (!resolved.empty()) protect_input(resolved, "a file of the OCIO config");
  return cs;
}

namespace {

// The sources of the FileTransforms in `t`, groups included.
void collect_file_sources(const OCIO::ConstTransformRcPtr& t, std::set<std::string>& out) {
  if (!t) return;
  if (auto group = std::dynamic_pointer_cast<const OCIO::GroupTransform>(t)) {
    for (int i = 0; i < group->getNumTransforms(); ++i)
      collect_file_sources(group->getTransform(i), out);
  } else if (auto file = std::dynamic_pointer_cast<const OCIO::FileTransform>(t)) {
    if (file->getSrc() && *file->getSrc()) out.insert(file->getSrc());
  }
}

std::string file_bytes(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::ostringstream text;
  text << f.rdbuf();
  return f ? text.str() : std::string("(unreadable)");
}

}  // namespace

std::vector<std::pair<std::string, std::string>> ColourSpaces::referenced_files() const {
  const ConfigPtr& config = config_of(config_);
  std::set<std::string> sources;
  const int spaces =
      config->getNumColorSpaces(OCIO::SEARCH_REFERENCE_SPACE_ALL, OCIO::COLORSPACE_ALL);
  for (int i = 0; i < spaces; ++i) {
    auto cs = config->getColorSpace(config->getColorSpaceNameByIndex(
        OCIO::SEARCH_REFERENCE_SPACE_ALL, OCIO::COLORSPACE_ALL, i));
    if (!cs) continue;
    collect_file_sources(cs->getTransform(OCIO::COLORSPACE_DIR_TO_REFERENCE), sources);
    collect_file_sources(cs->getTransform(OCIO::COLORSPACE_DIR_FROM_REFERENCE), sources);
  }
  for (int i = 0; i < config->getNumLooks(); ++i) {
    auto look = config->getLook(config->getLookNameByIndex(i));
    if (!look) continue;
    collect_file_sources(look->getTransform(), sources);
    collect_file_sources(look->getInverseTransform(), sources);
  }
  for (int i = 0; i < config->getNumViewTransforms(); ++i) {
    auto vt = config->getViewTransform(config->getViewTransformNameByIndex(i));
    if (!vt) continue;
    collect_file_sources(vt->getTransform(OCIO::VIEWTRANSFORM_DIR_TO_REFERENCE), sources);
    collect_file_sources(vt->getTransform(OCIO::VIEWTRANSFORM_DIR_FROM_REFERENCE), sources);
  }
  for (int i = 0; i < config->getNumNamedTransforms(OCIO::NAMEDTRANSFORM_ALL); ++i) {
    auto nt = config->getNamedTransform(
        config->getNamedTransformNameByIndex(OCIO::NAMEDTRANSFORM_ALL, i));
    if (!nt) continue;
    collect_file_sources(nt->getTransform(OCIO::TRANSFORM_DIR_FORWARD), sources);
    collect_file_sources(nt->getTransform(OCIO::TRANSFORM_DIR_INVERSE), sources);
  }
  std::vector<std::pair<std::string, std::string>> out;
  auto context = config->getCurrentContext();
  for (const std::string& src : sources) {
    std::string resolved;
    try {
      resolved = context->resolveFileLocation(src.c_str());
    } catch (const OCIO::Exception&) {
      // Not found: the transforms that need it fail when used, naming it.
    }
    out.emplace_back(src, resolved);
  }
  return out;
}

std::string ColourSpaces::content_identity() const {
  std::string bytes;
  if (!builtin_.empty()) {  // a built-in config: its text, as this OCIO serialises it
    std::ostringstream text;
    config_of(config_)->serialize(text);
    bytes = builtin_ + '\0' + text.str();
  } else {
    bytes = file_.empty() ? std::string(embedded::kOcioConfig) : file_bytes(file_);
  }
  std::uint64_t h = fnv1a(bytes);
  for (const auto& [src, resolved] : referenced_files()) {
    h = fnv1a(src + '\0', h);
    h = fnv1a(resolved.empty() ? std::string("(not found)") : file_bytes(resolved), h);
  }
  char buf[24];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
  return buf;
}

std::string ColourSpaces::resolve(std::string_view name) const {
  const ConfigPtr& config = config_of(config_);
  auto cs = config->getColorSpace(std::string(name).c_str());
  if (cs) return cs->getName();
  const bool interop = looks_like_interop_id(name);
  if (interop)
    if (std::string space = space_of_interop_id(name); !space.empty()) return space;
  std::string valid;
  for (const auto& d : describe()) valid += "\n  " + d;
  throw Error("unknown colour space " + quote(name) + " in OCIO config '" + origin_ + "'" +
              (interop ? " (no space of it has that interop ID)" : "") +
              ". Valid names (aliases in brackets):" + valid);
}

std::string ColourSpaces::space_of_interop_id(std::string_view id,
                                              const std::vector<std::string>& preferred) const {
  const ConfigPtr& config = config_of(config_);
  std::vector<std::string> candidates = preferred;
  for (const char* r : {"scene_linear", "rendering", "matte_paint", "color_picking",
                        "texture_paint", "aces_interchange", "data"})
    if (const std::string space = role(r); !space.empty()) candidates.push_back(space);
  for (std::string_view name : usual_names_of(id)) candidates.emplace_back(name);
  std::set<std::string> tried;
  auto has_id = [&](const std::string& space) {
    try {
      return facts(space).interop_id == id;
    } catch (const Error&) {  // a space OCIO cannot convert has no ID
      return false;
    }
  };
  for (const std::string& name : candidates) {
    // By the config's own names only: an interop ID is not looked up again.
    auto cs = config->getColorSpace(name.c_str());
    if (!cs || !tried.insert(cs->getName()).second) continue;
    if (has_id(cs->getName())) return cs->getName();
  }
  for (const std::string& space : names())
    if (!tried.count(space) && has_id(space)) return space;
  return "";
}

std::vector<std::string> ColourSpaces::names() const {
  const ConfigPtr& config = config_of(config_);
  std::vector<std::string> out;
  const int n = config->getNumColorSpaces(OCIO::SEARCH_REFERENCE_SPACE_ALL, OCIO::COLORSPACE_ALL);
  for (int i = 0; i < n; ++i)
    out.emplace_back(config->getColorSpaceNameByIndex(OCIO::SEARCH_REFERENCE_SPACE_ALL,
                                                      OCIO::COLORSPACE_ALL, i));
  return out;
}

std::vector<std::string> ColourSpaces::describe() const {
  const ConfigPtr& config = config_of(config_);
  std::vector<std::string> out;
  const int n = config->getNumColorSpaces(OCIO::SEARCH_REFERENCE_SPACE_ALL, OCIO::COLORSPACE_ALL);
  for (int i = 0; i < n; ++i) {
    const char* name =
        config->getColorSpaceNameByIndex(OCIO::SEARCH_REFERENCE_SPACE_ALL, OCIO::COLORSPACE_ALL, i);
    auto cs = config->getColorSpace(name);
    std::string line = name;
    if (cs && cs->getNumAliases() > 0) {
      line += " (";
      for (std::size_t a = 0; a < cs->getNumAliases(); ++a)
        line += (a ? ", " : "") + std::string(cs->getAlias(a));
      line += ")";
    }
    out.push_back(line);
  }
  return out;
}

ColourTransform ColourSpaces::to_xyz(std::string_view space) const {
  usable(space);
  return transform(space, true);
}

ColourTransform ColourSpaces::from_xyz(std::string_view space) const {
  usable(space);
  return transform(space, false);
}

ColourTransform ColourSpaces::transform(std::string_view space, bool to_xyz) const {
  const ConfigPtr& config = config_of(config_);
  ColourTransform t;
  t.source_ = resolve(space);
  try {
    const XyzRoute route = xyz_route_of(config, origin_);
    auto group = OCIO::GroupTransform::Create();
    auto convert = OCIO::ColorSpaceTransform::Create();
    convert->setSrc(to_xyz ? t.source_.c_str() : route.space.c_str());
    convert->setDst(to_xyz ? route.space.c_str() : t.source_.c_str());
    auto ap0 = OCIO::BuiltinTransform::Create();
    ap0->setStyle("UTILITY - ACES-AP0_to_CIE-XYZ-D65_BFD");
    ap0->setDirection(to_xyz ? OCIO::TRANSFORM_DIR_FORWARD : OCIO::TRANSFORM_DIR_INVERSE);
    if (!to_xyz && route.via_ap0) group->appendTransform(ap0);
    group->appendTransform(convert);
    if (to_xyz && route.via_ap0) group->appendTransform(ap0);
    auto processor = config->getProcessor(group);
    t.processor_ = std::make_shared<const CpuPtr>(exact_cpu_processor(processor));
  } catch (const OCIO::Exception& e) {
    throw Error("OCIO cannot convert between '" + t.source_ + "' and CIE-XYZ-D65: " + e.what());
  }
  return t;
}

ColourTransform ColourSpaces::display_from_xyz(const std::string& display,
                                               const std::string& view) const {
  const ConfigPtr& config = config_of(config_);
  ColourTransform t;
  const char* d = display.c_str();
  bool known = false;
  for (int i = 0; i < config->getNumDisplays(); ++i)
    known = known || display == config->getDisplay(i);
  if (!known) {
    std::string valid;
    for (int i = 0; i < config->getNumDisplays(); ++i)
      valid += (i ? ", " : "") + std::string(config->getDisplay(i));
    throw Error("unknown display " + quote(display) + " in OCIO config '" + origin_ +
                "' (valid: " + valid + ")");
  }
  const std::string v = view.empty() ? config->getDefaultView(d) : view;
  bool view_known = false;
  std::string views;
  for (int i = 0; i < config->getNumViews(d); ++i) {
    view_known = view_known || v == config->getView(d, i);
    views += (i ? ", " : "") + std::string(config->getView(d, i));
  }
  if (!view_known)
    throw Error("unknown view " + quote(v) + " of display '" + display + "' (valid: " + views +
                ")");
  t.source_ = display + " / " + v;
  // The view ends in a colour space: one no colour converts through is refused as by name.
  if (const std::string space = display_colour_space(display, v); !space.empty()) usable(space);
  try {
    const XyzRoute route = xyz_route_of(config, origin_);
    auto group = OCIO::GroupTransform::Create();
    if (route.via_ap0) {
      auto ap0 = OCIO::BuiltinTransform::Create();
      ap0->setStyle("UTILITY - ACES-AP0_to_CIE-XYZ-D65_BFD");
      ap0->setDirection(OCIO::TRANSFORM_DIR_INVERSE);
      group->appendTransform(ap0);
    }
    auto dv = OCIO::DisplayViewTransform::Create();
    dv->setSrc(route.space.c_str());
    dv->setDisplay(d);
    dv->setView(v.c_str());
    group->appendTransform(dv);
    auto processor = config->getProcessor(group);
    t.processor_ = std::make_shared<const CpuPtr>(exact_cpu_processor(processor));
  } catch (const OCIO::Exception& e) {
    throw Error("OCIO cannot convert CIE-XYZ-D65 to display '" + display + "', view '" + v +
                "': " + e.what());
  }
  return t;
}

std::string ColourSpaces::display_colour_space(const std::string& display,
                                               const std::string& view) const {
  const ConfigPtr& config = config_of(config_);
  const std::string v = view.empty() ? config->getDefaultView(display.c_str()) : view;
  std::string name = config->getDisplayViewColorSpaceName(display.c_str(), v.c_str());
  if (name == "<USE_DISPLAY_NAME>") name = display;  // OCIO's shared views
  auto cs = config->getColorSpace(name.c_str());
  return cs ? cs->getName() : "";
}

std::string ColourSpaces::role(std::string_view role) const {
  const ConfigPtr& config = config_of(config_);
  const std::string r(role);
  if (!config->hasRole(r.c_str())) return "";
  auto cs = config->getColorSpace(r.c_str());
  return cs ? cs->getName() : "";
}

std::string ColourSpaces::role_or_name(std::initializer_list<std::string_view> roles,
                                       std::initializer_list<std::string_view> names,
                                       std::string_view purpose) const {
  for (std::string_view r : roles)
    if (std::string space = role(r); !space.empty()) return space;
  const ConfigPtr& config = config_of(config_);
  for (std::string_view n : names)
    if (auto cs = config->getColorSpace(std::string(n).c_str())) return cs->getName();
  std::string missing;
  std::size_t i = 0;
  for (std::string_view r : roles)
    missing += (i++ == 0 ? "" : i == roles.size() ? " or " : ", ") + std::string(r);
  throw ConfigError("the OCIO config '" + origin_ + "' has no " + missing + " role" +
                    (names.size() ? " (nor a space named " + quote(*names.begin()) + ")" : "") +
                    " for " + std::string(purpose) + "; add the role to the config");
}

std::pair<std::string, std::string> ColourSpaces::file_rule(const std::string& path) const {
  // OCIO compiles each rule's expression on every match: paths no rule but the default can
  // match are told by the screen; OCIO decides the others, once each.
  if (!facts_->file_rules->may_match(path)) return {"", ""};
  const ConfigPtr& config = config_of(config_);
  count_work(Work::file_rule_match);
  size_t index = 0;
  const char* space = config->getColorSpaceFromFilepath(path.c_str(), index);
  if (index + 1 >= config->getFileRules()->getNumEntries()) return {"", ""};
  if (!space || !*space) return {"", ""};
  auto cs = config->getColorSpace(space);
  return {cs ? cs->getName() : space, config->getFileRules()->getName(index)};
}

NamedSpace ColourSpaces::named(std::string_view given) const {
  if (given.empty()) return {};
  return {std::string(given), &usable(given)};
}

const ColourSpaceFacts& ColourSpaces::usable(std::string_view space) const {
  const ColourSpaceFacts& f = facts(space);
  if (!f.unusable.empty())
    throw Error("colour space " + quote(f.name) + " of the OCIO config '" + origin_ +
                "' cannot be used: " + f.unusable);
  return f;
}

const ColourSpaceFacts& ColourSpaces::facts(std::string_view space) const {
  const std::string name = resolve(space);
  {
    std::lock_guard<std::mutex> lock(facts_->mutex);
    if (auto it = facts_->by_name.find(name); it != facts_->by_name.end()) return *it->second;
  }
  // Gathered unlocked (OCIO builds a processor); two threads asking at once keep the first.
  auto gathered = std::make_unique<const ColourSpaceFacts>(gather_facts(name));
  std::lock_guard<std::mutex> lock(facts_->mutex);
  return *facts_->by_name.emplace(name, std::move(gathered)).first->second;
}

ColourSpaceFacts ColourSpaces::gather_facts(const std::string& space) const {
  ColourSpaceFacts f;
  f.name = space;
  const auto cs = config_of(config_)->getColorSpace(space.c_str());
  f.encoding = cs->getEncoding() ? cs->getEncoding() : "";
  f.interop_id = ocio_compat::interop_id(cs);
  f.interop_id_from_config = !f.interop_id.empty();
  f.display_referred = cs->getReferenceSpaceType() == OCIO::REFERENCE_SPACE_DISPLAY;
  f.data = cs->isData() || f.encoding == "data" || f.interop_id == "data";
  if (f.data) {
    f.interop_id = "data";
    return f;
  }
  const ColourTransform t = transform(space, true);
  f.white = t(1, 1, 1);
  // The unit colours as columns: the matrix of a linear space, and the primaries' directions
  // of any space whose curve keeps 0 and 1 (sRGB, a gamma).
  const Mat3 m = from_columns(t(1, 0, 0), t(0, 1, 0), t(0, 0, 1));
  const bool finite = std::all_of(m.begin(), m.end(), [](double v) { return std::isfinite(v); });
  if (finite && std::abs(det(m)) > 1e-9) f.rgb_to_xyz = m;
  // Linear: the conversion is that matrix, inside and outside [0, 1], negative and above 1 (a
  // curve, a clamp or an offset shows).
  if (f.rgb_to_xyz && t(0, 0, 0).max_abs() <= 1e-7) {
    const Xyz probes[] = {{0.8, 0.5, 0.2},     {0.08, 0.05, 0.02}, {0.2, 0.5, 0.7},
                          {0.01, 0.003, 0.02}, {-0.1, 0.4, 0.2},   {1.5, 2.5, 0.3}};
    f.linear = std::all_of(std::begin(probes), std::end(probes), [&](const Xyz& c) {
      return relative_error(t(c.X, c.Y, c.Z), mul(*f.rgb_to_xyz, c)) <= 1e-5;
    });
  }
  // Primaries along their directions from mid grey: t(1, g, g) - t(g, g, g) is the red primary
  // times c(1) - c(g) for any per-channel curve c (also a log curve, where c(0) is not 0).
  const Xyz mid = t(0.5, 0.5, 0.5);
  const Xyz dirs[4] = {t(1, 0.5, 0.5) - mid, t(0.5, 1, 0.5) - mid, t(0.5, 0.5, 1) - mid, f.white};
  f.unusable = unusable_reason(t);
  if (!f.unusable.empty()) return f;
  std::array<float, 8> xy{};
  bool primaries = true;
  for (int k = 0; k < 4; ++k) {
    const double sum = dirs[k].sum();
    primaries = primaries && std::abs(sum) > 1e-9 && dirs[k].finite();
    if (primaries) {
      xy[2 * k] = static_cast<float>(dirs[k].X / sum);
      xy[2 * k + 1] = static_cast<float>(dirs[k].Y / sum);
    }
  }
  if (!primaries) return f;
  f.primaries_d65 = xy;
  const KnownPrimaries* known = known_primaries_of(xy.data());
  // A known space is tagged with its standard's own primaries and white, as files expect.
  f.chromaticities = known ? known->native : xy;
  // The encoding: linear as measured above; else greys keep the white's chromaticity, so
  // Y(v) / Y(1) is the curve at v.
  const KnownEncoding* encoding = nullptr;
  if (f.linear) {
    encoding = &known_encodings().front();
  } else if (std::abs(f.white.Y) > 1e-12) {
    for (const KnownEncoding& e : known_encodings().subspan(1)) {
      bool same = true;
      for (double v : {0.01, 0.03, 0.1, 0.3, 0.5, 0.8}) {
        const double want = e(v), got = t(v, v, v).Y / f.white.Y;
        // 563/256 and 2.2 differ by 4e-3 at 0.01.
        same = same && std::abs(got - want) <= 1e-3 * want + 1e-6;
      }
      if (same) {
        encoding = &e;
        break;
      }
    }
  }
  if (encoding) f.transfer = encoding->transfer;
  // Measured: the curve on known primaries, scene- or display-referred, when the Color Interop
  // Forum names that.
  if (!f.interop_id_from_config && known && encoding)
    f.interop_id = known_interop_id(encoding->id, known->id, f.display_referred);
  return f;
}

bool ColourSpaces::is_data(std::string_view space) const {
  // An unknown name is no data space (resolve() names the valid ones where it matters).
  if (!config_of(config_)->getColorSpace(std::string(space).c_str())) return false;
  return facts(space).data;
}

bool ColourSpaces::is_linear(std::string_view space) const {
  return facts(space).linear;
}

std::optional<std::array<float, 8>> ColourSpaces::primaries_d65(std::string_view space) const {
  return facts(space).primaries_d65;
}

bool ColourSpaces::is_display_referred(std::string_view space) const {
  return facts(space).display_referred;
}

std::optional<std::array<float, 8>> ColourSpaces::chromaticities(std::string_view space) const {
  return facts(space).chromaticities;
}

std::optional<IccTransfer> ColourSpaces::transfer(std::string_view space) const {
  return facts(space).transfer;
}

std::string ColourSpaces::interop_id(std::string_view space) const {
  return facts(space).interop_id;
}

std::string ColourSpaces::linear_twin(std::string_view space) const {
  const ColourSpaceFacts& f = facts(space);
  if (f.data || !f.primaries_d65) return "";
  if (f.linear && !f.display_referred) return f.name;
  // By interop ID: "<curve>_<primaries>_<reference>" has the twin "lin_<primaries>_scene".
  const std::size_t first = f.interop_id.find('_'), last = f.interop_id.rfind('_');
  const std::string id = first != std::string::npos && last > first
                             ? "lin_" + f.interop_id.substr(first + 1, last - first - 1) + "_scene"
                             : "";
  std::string by_primaries;
  for (const std::string& name : names()) {
    try {
      const ColourSpaceFacts& o = facts(name);
      if (o.data || !o.linear || o.display_referred || !o.primaries_d65) continue;
      if (!id.empty() && o.interop_id == id) return o.name;
      if (by_primaries.empty() &&
          chromaticity_difference(o.primaries_d65->data(), f.primaries_d65->data()) <= 2e-4)
        by_primaries = o.name;
    } catch (const Error&) {  // a space OCIO cannot convert: not a twin
    }
  }
  return by_primaries;
}

}  // namespace spectralize
