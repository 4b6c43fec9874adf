#pragma once
// Where OpenColorIO 2.1 (Debian 12) and 2.2 to 2.5 (the VFX Reference Platform CY2026) differ,
// decided here once (docs/DESIGN.md §11). Included by colour_space.cpp only: OCIO's headers stay
// out of every header the other layers include.

#include <OpenColorIO/OpenColorIO.h>

#include <string>

namespace spectralize::ocio_compat {

namespace OCIO = OCIO_NAMESPACE;

/// Built-in configs by URI (ocio://default, ocio://cg-config-latest, ...): OCIO 2.2 and later.
inline constexpr bool kBuiltinConfigs = OCIO_VERSION_HEX >= 0x02020000;

/// The interop ID the config gives a colour space (OCIO 2.5's ColorSpace::getInteropID), or ""
/// where the config or this OCIO has none. Cost: O(1).
inline std::string interop_id(const OCIO::ConstColorSpaceRcPtr& cs) {
#if OCIO_VERSION_HEX >= 0x02050000
  const char* id = cs ? cs->getInteropID() : nullptr;
  return id ? id : "";
#else
  (void)cs;
  return "";
#endif
}

/// The config a built-in URI names ("ocio://default" and the like) and the name it resolves to
/// ("ocio://cg-config-v4.0.0_aces-v2.0_ocio-v2.5"); throws OCIO::Exception for an unknown one,
/// and on OCIO 2.1 (which has none). Cost: parsing the built-in config.
inline OCIO::ConstConfigRcPtr builtin_config(const std::string& uri, std::string& resolved) {
#if OCIO_VERSION_HEX >= 0x02020000
  const char* r = OCIO::ResolveConfigPath(uri.c_str());
  resolved = r ? r : uri;
  return OCIO::Config::CreateFromFile(uri.c_str());
#else
  resolved = uri;
  throw OCIO::Exception("built-in configs need OpenColorIO 2.2 or later");
#endif
}

}  // namespace spectralize::ocio_compat
