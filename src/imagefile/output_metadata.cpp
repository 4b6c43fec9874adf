#include "imagefile/output_metadata.h"
#include "text/strings.h"

#include <charconv>
#include <cstdlib>
#include <ctime>

namespace spectralize {

namespace {

std::string exif_time(std::time_t t, bool utc) {
  std::tm tm{};
  if (utc ? !gmtime_r(&t, &tm) : !localtime_r(&t, &tm)) return "";
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y:%m:%d %H:%M:%S", &tm);
  return buf;
}

}  // namespace

std::string output_date_time(std::string& warning) {
  warning.clear();
  const char* epoch = std::getenv("SOURCE_DATE_EPOCH");
  if (epoch && *epoch) {
    const std::string_view text(epoch);
    long long seconds = -1;
    auto r = std::from_chars(text.data(), text.data() + text.size(), seconds);
    // 253402300799 is 9999-12-31 23:59:59 UTC: EXIF's DateTime has four year digits.
    if (r.ec == std::errc() && r.ptr == text.data() + text.size() && seconds >= 0 &&
        seconds <= 253402300799ll)
      return exif_time(static_cast<std::time_t>(seconds), true);
    warning = "SOURCE_DATE_EPOCH '" + clip(text) +
              "' is not a whole number of seconds from 0 to 253402300799; ignored (DateTime "
              "is now)";
  }
  return exif_time(std::time(nullptr), false);
}

bool carried_over_attribute(const std::string& name) {
  static const char* const dropped_prefixes[] = {
      "oiio:", "openexr:", "exr:",   "png:", "jpeg:",      "tiff:",
      "hdr:",  "rla:",     "targa:", "bmp:", "ICCProfile", "spectralize:"};
  static const char* const dropped[] = {"compression",
                                        "Compression",
                                        "chromaticities",
                                        "colorInteropID",
                                        "planarconfig",
                                        "Software",
                                        "DateTime",
                                        "spectralLayoutVersion",
                                        "emissiveUnits",
                                        "polarisationHandedness",
                                        "tile_width",
                                        "tile_height",
                                        "EV",
                                        "colorspace",
                                        "textureformat",
                                        "wrapmodes"};
  for (const char* p : dropped_prefixes)
    if (name.rfind(p, 0) == 0) return false;
  for (const char* d : dropped)
    if (name == d) return false;
  return true;
}

}  // namespace spectralize
