#include "io/colour_space.h"

#include <OpenColorIO/OpenColorIO.h>

#include <cstdlib>
#include <sstream>

#include "core/error.h"

namespace OCIO = OCIO_NAMESPACE;

namespace spectralize {

namespace embedded {
extern const std::string_view kOcioConfig;
}

namespace {

using ConfigPtr = OCIO::ConstConfigRcPtr;
using CpuPtr = OCIO::ConstCPUProcessorRcPtr;

const ConfigPtr& config_of(const std::shared_ptr<const void>& p) {
  return *static_cast<const ConfigPtr*>(p.get());
}

// The XYZ-D65 space of a config: the cie_xyz_d65_interchange role, else a space so named.
std::string xyz_space_of(const ConfigPtr& config) {
  if (config->hasRole("cie_xyz_d65_interchange")) {
    auto cs = config->getColorSpace("cie_xyz_d65_interchange");
    if (cs) return cs->getName();
  }
  for (const char* name : {"CIE-XYZ-D65", "CIE XYZ-D65 - Scene-referred", "cie_xyz_d65"}) {
    auto cs = config->getColorSpace(name);
    if (cs) return cs->getName();
  }
  throw Error(
      "the OCIO config has no CIE-XYZ-D65 colour space (nor a cie_xyz_d65_interchange "
      "role) to convert into");
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

ColourSpaces ColourSpaces::load(const std::string& explicit_path) {
  ColourSpaces cs;
  ConfigPtr config;
  std::string where;
  try {
    if (!explicit_path.empty()) {
      where = explicit_path;
      config = OCIO::Config::CreateFromFile(explicit_path.c_str());
      cs.origin_ = explicit_path;
    } else if (const char* env = std::getenv("OCIO"); env && *env) {
      where = std::string("$OCIO=") + env;
      config = OCIO::Config::CreateFromFile(env);
      cs.origin_ = where;
    } else {
      where = "the shipped config";
      std::istringstream text{std::string(embedded::kOcioConfig)};
      config = OCIO::Config::CreateFromStream(text);
      cs.origin_ = "shipped";
    }
    config->validate();
  } catch (const OCIO::Exception& e) {
    throw Error("OCIO config '" + where + "': " + e.what());
  }
  cs.config_ = std::make_shared<const ConfigPtr>(config);
  return cs;
}

std::string ColourSpaces::resolve(std::string_view name) const {
  const ConfigPtr& config = config_of(config_);
  auto cs = config->getColorSpace(std::string(name).c_str());
  if (cs) return cs->getName();
  std::string valid;
  for (const auto& d : describe()) valid += "\n  " + d;
  throw Error("unknown colour space '" + std::string(name) + "' in OCIO config '" + origin_ +
              "'. Valid names (aliases in brackets):" + valid);
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
    const std::string xyz = xyz_space_of(config);
    auto processor = to_xyz ? config->getProcessor(t.source_.c_str(), xyz.c_str())
                            : config->getProcessor(xyz.c_str(), t.source_.c_str());
    t.processor_ = std::make_shared<const CpuPtr>(processor->getDefaultCPUProcessor());
  } catch (const OCIO::Exception& e) {
    throw Error("OCIO cannot convert between '" + t.source_ + "' and CIE-XYZ-D65: " + e.what());
  }
  return t;
}

}  // namespace spectralize
