#pragma once
// What the unit tests of batch ingest share (ingest_plan_test.cpp, ingest_test.cpp): small
// libraries of PNGs, and requests for them.

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "ingest/ingest.h"

namespace spectralize::test {

/// A 4 x 4 8-bit RGB PNG of one colour (its folders made).
inline void write_png(const std::filesystem::path& path, unsigned char value = 120) {
  std::filesystem::create_directories(path.parent_path());
  const OIIO::ImageSpec spec(4, 4, 3, OIIO::TypeUInt8);
  std::vector<unsigned char> px(4 * 4 * 3, value);
  auto out = OIIO::ImageOutput::create(path.string());
  ASSERT_TRUE(out && out->open(path.string(), spec)) << OIIO::geterror();
  ASSERT_TRUE(out->write_image(OIIO::TypeUInt8, px.data()));
  ASSERT_TRUE(out->close());
}

/// A request for these sources into `destination`, on two threads.
inline IngestRequest request_for(std::vector<std::string> sources, const std::string& destination) {
  IngestRequest r;
  r.sources = std::move(sources);
  r.destination = destination;
  r.settings.threads = 2;
  return r;
}

}  // namespace spectralize::test
