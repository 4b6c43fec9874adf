#pragma once
// What the unit tests of the file layers share: a fresh folder per test, and image specs with
// given channel names.

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

#include "imagefile/oiio_compat.h"

namespace spectralize::test {

/// A fresh folder under gtest's temporary directory, named for the test, removed afterwards.
struct TempDir {
  std::filesystem::path dir;
  explicit TempDir(const std::string& prefix) {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir = std::filesystem::path(::testing::TempDir()) /
          (prefix + "_" + std::to_string(::getpid()) + "_" + info->name());
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);
  }
  std::string operator/(const std::string& name) const { return (dir / name).string(); }
};

/// What oiio:ColorSpace holds for a space of this name and interop ID, as this OIIO expects it:
/// the name with OIIO 2, the interop ID with OIIO 3 (imagefile/oiio_compat.h).
inline std::string oiio_colour_space(const std::string& name, const std::string& interop_id) {
  return oiio_compat::kInteropColourSpaceNames ? interop_id : name;
}

/// A `width` x `height` spec with these channels and no alpha.
inline OIIO::ImageSpec spec_of(std::vector<std::string> names,
                               OIIO::TypeDesc type = OIIO::TypeFloat, int width = 8,
                               int height = 8) {
  OIIO::ImageSpec spec(width, height, static_cast<int>(names.size()), type);
  spec.channelnames = std::move(names);
  spec.alpha_channel = -1;
  return spec;
}

}  // namespace spectralize::test
