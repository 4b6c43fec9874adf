// The metadata every written image shares (imagefile/output_metadata.h): SOURCE_DATE_EPOCH gives
// the EXIF DateTime of that second in UTC, whatever the time zone, over its whole documented
// range (0 to the last second of the year 9999); anything else in it is ignored with a warning
// that names it, and the DateTime is then the time now in local time; the input attributes
// carried over are those that describe the image (artist, copyright, camera), never its
// encoding, its colour or spectralize's own. Oracles: published dates of Unix times, the clock
// read here and formatted for a fixed POSIX time zone, and the attribute names OIIO and OpenEXR
// give those roles.

#include "imagefile/output_metadata.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <ctime>
#include <optional>
#include <regex>
#include <string>

namespace spectralize {
namespace {

// Sets an environment variable for the life of the object, then restores it (and the zone).
class ScopedEnv {
 public:
  ScopedEnv(const char* name, std::optional<std::string> value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    if (value)
      ::setenv(name, value->c_str(), 1);
    else
      ::unsetenv(name);
    ::tzset();
  }
  ~ScopedEnv() {
    if (old_)
      ::setenv(name_, old_->c_str(), 1);
    else
      ::unsetenv(name_);
    ::tzset();
  }

 private:
  const char* name_;
  std::optional<std::string> old_;
};

// "YYYY:MM:DD hh:mm:ss" of `t` shifted by `offset_hours`, formatted as UTC.
std::string utc_text(std::time_t t, int offset_hours = 0) {
  t += offset_hours * 3600;
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y:%m:%d %H:%M:%S", &tm);
  return buf;
}

const std::regex kExifDateTime(R"(\d{4}:\d{2}:\d{2} \d{2}:\d{2}:\d{2})");

TEST(OutputMetadata, SourceDateEpochIsThatSecondInUtcWhateverTheTimeZone) {
  // EST5: five hours behind UTC all year (a POSIX zone, no tz database needed).
  const ScopedEnv zone("TZ", "EST5");
  const std::pair<const char*, const char*> known[] = {
      {"0", "1970:01:01 00:00:00"},
      {"951782400", "2000:02:29 00:00:00"},   // a leap day
      {"1000000000", "2001:09:09 01:46:40"},  // the billennium
      {"1700000000", "2023:11:14 22:13:20"},
      {"253402300799", "9999:12:31 23:59:59"},  // the last second EXIF's four digits hold
  };
  for (const auto& [epoch, date] : known) {
    const ScopedEnv env("SOURCE_DATE_EPOCH", epoch);
    std::string warning = "left from before";
    EXPECT_EQ(output_date_time(warning), date) << epoch;
    EXPECT_EQ(warning, "") << epoch;  // cleared: nothing to say
  }
}

TEST(OutputMetadata, AnUnusableSourceDateEpochIsIgnoredNamingItAndTheTimeIsNowLocal) {
  const ScopedEnv zone("TZ", "EST5");
  for (const char* bad : {"253402300800", "-1", "12abc", " 5", "5 ", "1.5", "0x10", "+7",
                          "99999999999999999999999"}) {
    const ScopedEnv env("SOURCE_DATE_EPOCH", bad);
    std::string warning;
    const std::time_t before = std::time(nullptr);
    const std::string date = output_date_time(warning);
    const std::time_t after = std::time(nullptr);
    EXPECT_NE(warning.find("SOURCE_DATE_EPOCH"), std::string::npos) << bad << ": " << warning;
    EXPECT_NE(warning.find(std::string("'") + bad + "'"), std::string::npos) << warning;
    EXPECT_NE(warning.find("ignored"), std::string::npos) << warning;
    // Now, in local time (EST5: UTC - 5 h); the text's order is the time's.
    EXPECT_TRUE(std::regex_match(date, kExifDateTime)) << date;
    EXPECT_GE(date, utc_text(before, -5)) << bad;
    EXPECT_LE(date, utc_text(after, -5)) << bad;
  }
  // A value of a megabyte is named shortened, not echoed whole.
  const ScopedEnv env("SOURCE_DATE_EPOCH", std::string(1 << 20, '9'));
  std::string warning;
  output_date_time(warning);
  EXPECT_NE(warning.find("SOURCE_DATE_EPOCH"), std::string::npos);
  EXPECT_LT(warning.size(), 400u);
}

TEST(OutputMetadata, WithoutSourceDateEpochTheTimeIsNowLocalWithoutAWarning) {
  const ScopedEnv zone("TZ", "UTC-3");  // three hours ahead of UTC
  for (const std::optional<std::string>& value : {std::optional<std::string>(), {""}}) {
    const ScopedEnv env("SOURCE_DATE_EPOCH", value);
    std::string warning = "left from before";
    const std::time_t before = std::time(nullptr);
    const std::string date = output_date_time(warning);
    const std::time_t after = std::time(nullptr);
    EXPECT_EQ(warning, "");
    EXPECT_GE(date, utc_text(before, 3));
    EXPECT_LE(date, utc_text(after, 3));
  }
}

TEST(OutputMetadata, WhatDescribesTheImageIsCarriedOver) {
  // EXIF, IPTC and XMP fields and the TIFF/EXR descriptive tags, as OIIO names them.
  for (const char* name : {"Artist", "Copyright", "ImageDescription", "DocumentName", "Make",
                           "Model", "Exif:ExposureTime", "Exif:FNumber", "Exif:LensModel",
                           "IPTC:Caption", "IPTC:Keywords", "XMP:Rating", "GPS:Latitude", "owner",
                           "comments", "capDate", "worldToCamera", "HostComputer"}) {
    EXPECT_TRUE(carried_over_attribute(name)) << name;
  }
}

TEST(OutputMetadata, EncodingColourAndSpectralizesOwnAttributesAreNotCarriedOver) {
  // Encoding: how the input was stored, not what the written file is.
  for (const char* name : {"compression",
                           "Compression",
                           "planarconfig",
                           "tile_width",
                           "tile_height",
                           "oiio:BitsPerSample",
                           "oiio:UnassociatedAlpha",
                           "openexr:lineOrder",
                           "openexr:dwaCompressionLevel",
                           "exr:chunkCount",
                           "png:compressionLevel",
                           "jpeg:subsampling",
                           "tiff:RowsPerStrip",
                           "tiff:Compression",
                           "hdr:exposure",
                           "rla:Gamma",
                           "targa:ImageID",
                           "bmp:version",
                           "textureformat",
                           "wrapmodes"})
    EXPECT_FALSE(carried_over_attribute(name)) << name;
  // Colour: the written RGB is tagged anew.
  for (const char* name : {"oiio:ColorSpace", "oiio:Gamma", "chromaticities", "colorInteropID",
                           "ICCProfile", "ICCProfile:profile_description", "colorspace", "EV"})
    EXPECT_FALSE(carried_over_attribute(name)) << name;
  // spectralize's own, and what it sets for every file it writes.
  for (const char* name : {"spectralize:mode", "spectralize:wavelengths", "spectralLayoutVersion",
                           "emissiveUnits", "polarisationHandedness", "Software", "DateTime"})
    EXPECT_FALSE(carried_over_attribute(name)) << name;
}

TEST(OutputMetadata, OnlyANamesBeginningMarksItsFamily) {
  // A family prefix elsewhere in a name, or a dropped name as part of another, is another name.
  for (const char* name : {"my_oiio:note", "Exif:compression", "XMP:spectralize:note",
                           "DateTimeOriginal", "Software_version", "CompressionNote"})
    EXPECT_TRUE(carried_over_attribute(name)) << name;
}

}  // namespace
}  // namespace spectralize
