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

bool ColourSpaces::has_builtin_configs() {
  return ocio_compat::kBuiltinConfigs;
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
    if (!explicit_path.empty()) throw Error(why);
    throw ConfigError("OCIO config '$OCIO=" + source + "': " + why);
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
  std::string valid;
  for (const auto& d : describe()) valid += "\n  " + d;
  throw Error("unknown colour space " + quote(name) + " in OCIO config '" + origin_ +
              "'. Valid names (aliases in brackets):" + valid);
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
  return transform(space, true);
}

ColourTransform ColourSpaces::from_xyz(std::string_view space) const {
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

namespace {

// Known primaries and whites (red, green, blue, white as CIE xy): the standard's own (what an
// EXR chromaticities attribute says) and as a D65-referred config sees them after its Bradford
// adaptation to D65 (measured through OCIO's built-in ACES transforms).
struct KnownSpace {
  const char* primaries;  // the interop ID's primaries part: "rec709", "ap1", ...
  std::array<float, 8> native, adapted;
};
constexpr float kD65x = 0.3127f, kD65y = 0.3290f;
// clang-format off
const KnownSpace kKnown[] = {
    {"rec709",
     {0.64f, 0.33f, 0.30f, 0.60f, 0.15f, 0.06f, kD65x, kD65y},
     {0.64f, 0.33f, 0.30f, 0.60f, 0.15f, 0.06f, kD65x, kD65y}},
    {"rec2020",
     {0.708f, 0.292f, 0.170f, 0.797f, 0.131f, 0.046f, kD65x, kD65y},
     {0.708f, 0.292f, 0.170f, 0.797f, 0.131f, 0.046f, kD65x, kD65y}},
    {"p3d65",
     {0.680f, 0.320f, 0.265f, 0.690f, 0.150f, 0.060f, kD65x, kD65y},
     {0.680f, 0.320f, 0.265f, 0.690f, 0.150f, 0.060f, kD65x, kD65y}},
    {"adobergb",
     {0.64f, 0.33f, 0.21f, 0.71f, 0.15f, 0.06f, kD65x, kD65y},
     {0.64f, 0.33f, 0.21f, 0.71f, 0.15f, 0.06f, kD65x, kD65y}},
    {"ap1",
     {0.713f, 0.293f, 0.165f, 0.830f, 0.128f, 0.044f, 0.32168f, 0.33767f},
     {0.713196f, 0.292689f, 0.159509f, 0.838789f, 0.128673f, 0.043896f, kD65x, kD65y}},
    {"ap0",
     {0.7347f, 0.2653f, 0.0f, 1.0f, 0.0001f, -0.077f, 0.32168f, 0.33767f},
     {0.734855f, 0.264225f, -0.006171f, 1.011315f, 0.015968f, -0.064236f, kD65x, kD65y}},
    {"ciexyzd65",
     {1.0f, 0.0f, 0.0f, 1.0f, 0.0f, 0.0f, 1 / 3.0f, 1 / 3.0f},
     {1.0f, 0.0f, 0.0f, 1.0f, 0.0f, 0.0f, 1 / 3.0f, 1 / 3.0f}},
};
// clang-format on

// The interop IDs of the Color Interop Forum that a measurement can tell apart: a transfer
// that is linear, the sRGB curve or a pure gamma, on known primaries, scene- or
// display-referred.
const char* const kInteropIds[] = {
    "lin_rec709_scene",   "lin_rec2020_scene",  "lin_p3d65_scene",      "lin_adobergb_scene",
    "lin_ap1_scene",      "lin_ap0_scene",      "lin_ciexyzd65_scene",  "srgb_rec709_scene",
    "g22_rec709_scene",   "g18_rec709_scene",   "srgb_ap1_scene",       "g22_ap1_scene",
    "srgb_p3d65_scene",   "g22_adobergb_scene", "srgb_rec709_display",  "g24_rec709_display",
    "g22_rec709_display", "srgb_p3d65_display", "g22_adobergb_display", "g26_p3d65_display"};

// Bradford's cone response matrix (Lam 1985), and its inverse.
constexpr double kBradford[3][3] = {
    {0.8951, 0.2664, -0.1614}, {-0.7502, 1.7135, 0.0367}, {0.0389, -0.0685, 1.0296}};
constexpr double kBradfordInverse[3][3] = {{0.986992905, -0.147054256, 0.159962652},
                                           {0.43230527, 0.518360272, 0.049291228},
                                           {-0.008528665, 0.040042822, 0.968486696}};

using Vec3 = std::array<double, 3>;

Vec3 mul(const double m[3][3], const Vec3& v) {
  return {m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2],
          m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2],
          m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2]};
}

Vec3 xyz_of_xy(double x, double y) {
  return {x / y, 1.0, (1 - x - y) / y};
}

}  // namespace

std::array<float, 8> adapt_chromaticities_to_d65(const float* xy) {
  // RGB -> XYZ of the file's primaries, scaled so that RGB 1 is its white.
  Vec3 p[3];
  for (int i = 0; i < 3; ++i) p[i] = xyz_of_xy(xy[2 * i], xy[2 * i + 1]);
  const Vec3 w = xyz_of_xy(xy[6], xy[7]);
  const double det = p[0][0] * (p[1][1] * p[2][2] - p[2][1] * p[1][2]) -
                     p[1][0] * (p[0][1] * p[2][2] - p[2][1] * p[0][2]) +
                     p[2][0] * (p[0][1] * p[1][2] - p[1][1] * p[0][2]);
  std::array<float, 8> out{};
  if (!(std::abs(det) > 1e-12) || !(xy[7] > 0) || !(xy[1] > 0) || !(xy[3] > 0) || !(xy[5] != 0)) {
    for (int i = 0; i < 8; ++i) out[i] = xy[i];
    return out;
  }
  // Scales s with sum_i s_i p_i = w (Cramer's rule).
  auto det3 = [](const Vec3& a, const Vec3& b, const Vec3& c) {
    return a[0] * (b[1] * c[2] - c[1] * b[2]) - b[0] * (a[1] * c[2] - c[1] * a[2]) +
           c[0] * (a[1] * b[2] - b[1] * a[2]);
  };
  const double s[3] = {det3(w, p[1], p[2]) / det, det3(p[0], w, p[2]) / det,
                       det3(p[0], p[1], w) / det};
  // Von Kries in Bradford's cone space, from the white to D65.
  const Vec3 from = mul(kBradford, w), to = mul(kBradford, xyz_of_xy(kD65x, kD65y));
  for (int i = 0; i < 3; ++i) {
    Vec3 c = mul(kBradford, {p[i][0] * s[i], p[i][1] * s[i], p[i][2] * s[i]});
    for (int k = 0; k < 3; ++k) c[k] *= to[k] / from[k];
    const Vec3 a = mul(kBradfordInverse, c);
    const double sum = a[0] + a[1] + a[2];
    out[2 * i] = static_cast<float>(a[0] / sum);
    out[2 * i + 1] = static_cast<float>(a[1] / sum);
  }
  out[6] = kD65x;
  out[7] = kD65y;
  return out;
}

double chromaticity_difference(const float* a, const float* b) {
  double d = 0;
  for (int i = 0; i < 8; ++i) d = std::max(d, std::abs(static_cast<double>(a[i]) - b[i]));
  return d;
}

std::string interop_id_of_chromaticities(const float* xy) {
  const std::array<float, 8> adapted = adapt_chromaticities_to_d65(xy);
  for (const KnownSpace& k : kKnown)
    if (chromaticity_difference(k.adapted.data(), adapted.data()) <= kChromaticityTolerance)
      return std::string("lin_") + k.primaries + "_scene";
  return "";
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
  const ColourTransform t = to_xyz(space);
  // Linear maps scale: f(k c) = k f(c), for two scales on a colour of distinct components.
  const Xyz a = t(0.8, 0.5, 0.2), b = t(0.4, 0.25, 0.1), c = t(0.08, 0.05, 0.02), o = t(0, 0, 0);
  auto close = [](const Xyz& x, const Xyz& y) {
    return (x - y).max_abs() <= 1e-5 * std::max(1e-3, y.max_abs());
  };
  f.linear = o.max_abs() <= 1e-7 && close(b, 0.5 * a) && close(c, 0.1 * a);
  // Primaries along their directions from mid grey: t(1, g, g) - t(g, g, g) is the red primary
  // times c(1) - c(g) for any per-channel curve c (also a log curve, where c(0) is not 0).
  const Xyz mid = t(0.5, 0.5, 0.5), white = t(1, 1, 1);
  const Xyz dirs[4] = {t(1, 0.5, 0.5) - mid, t(0.5, 1, 0.5) - mid, t(0.5, 0.5, 1) - mid, white};
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
  const KnownSpace* known = nullptr;
  for (const KnownSpace& k : kKnown)
    if (!known && chromaticity_difference(k.adapted.data(), xy.data()) <= kChromaticityTolerance)
      known = &k;
  // A known space is tagged with its standard's own primaries and white, as files expect.
  f.chromaticities = known ? known->native : xy;
  // The transfer: greys keep the white's chromaticity, so Y(v) / Y(1) is the curve at v.
  if (std::abs(white.Y) > 1e-12) {
    auto matches = [&](auto&& curve) {
      for (double v : {0.01, 0.03, 0.1, 0.3, 0.5, 0.8}) {
        const double want = curve(v), got = t(v, v, v).Y / white.Y;
        // 563/256 and 2.2 differ by 4e-3 at 0.01.
        if (!(std::abs(got - want) <= 1e-3 * want + 1e-6)) return false;
      }
      return true;
    };
    if (matches([](double v) { return v; })) {
      f.transfer = IccTransfer{IccTransfer::linear, 1};
    } else if (matches([](double v) {
                 return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
               })) {
      f.transfer = IccTransfer{IccTransfer::srgb, 2.4};
    } else {
      for (double g : {563.0 / 256, 2.2, 2.4, 1.8, 2.6})
        if (!f.transfer && matches([g](double v) { return std::pow(v, g); }))
          f.transfer = IccTransfer{IccTransfer::gamma, g};
    }
  }
  if (f.interop_id_from_config || !known) return f;
  // Measured: the curve, recognised by its value at 0.5 (linear 0.5, the sRGB curve 0.2140, a
  // gamma of 2.2 or Adobe's 563/256 0.2176, 1.8 0.2872, 2.4 0.1895, 2.6 0.1649), on known
  // primaries, scene- or display-referred, when the Color Interop Forum names that.
  std::string curve;
  if (f.linear) {
    curve = "lin";
  } else if (std::abs(white.Y) > 1e-12) {
    const double v = mid.Y / white.Y;
    const std::pair<const char*, double> curves[] = {
        {"srgb", 0.21404}, {"g22", 0.21764}, {"g18", 0.28717}, {"g24", 0.18946}, {"g26", 0.16494}};
    for (const auto& [name, at_half] : curves)
      if (std::abs(v - at_half) < 1e-3) curve = name;
  }
  if (curve.empty()) return f;
  const std::string id =
      curve + "_" + known->primaries + (f.display_referred ? "_display" : "_scene");
  for (const char* k : kInteropIds)
    if (id == k) f.interop_id = id;
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
