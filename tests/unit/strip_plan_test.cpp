// The strip plan of the streamed jobs (imagefile/strip_plan.h): whole compression blocks, enough
// blocks per write for every compression worker, memory bounded; checked
// over widths from 1K to 64K, 81 and 401 bands, every OpenEXR block height, 1 to 16 workers.

#include <gtest/gtest.h>

#include <numeric>

#include "imagefile/strip_plan.h"

namespace spectralize {
namespace {

constexpr std::size_t kMB = 1u << 20;

TEST(StripPlan, WholeBlocksForEveryWorkerWithinTheBudget) {
  for (int width : {1024, 4096, 8192, 16384, 65536})
    for (int channels : {84, 404})
      for (std::size_t sample : {2u, 4u})
        for (int block : {1, 16, 32, 256})
          for (int workers : {1, 2, 4, 16})
            for (int height : {1, 7, 2048, 8192}) {
              const std::size_t row = static_cast<std::size_t>(width) * channels * sample;
              const int rows = strip_rows(height, block, row, workers);
              SCOPED_TRACE(testing::Message()
                           << width << "x" << height << " " << channels << "ch " << sample
                           << "B block " << block << " workers " << workers);
              ASSERT_GE(rows, 1);
              ASSERT_LE(rows, height);
              if (rows == height) continue;  // the whole image in one strip
              const int unit = block;
              EXPECT_EQ(rows % unit, 0) << rows;  // whole blocks
              const std::size_t bytes = static_cast<std::size_t>(rows) * row;
              // Bounded: 192 MB per strip buffer, or one unit where a unit is larger.
              EXPECT_LE(bytes, std::max<std::size_t>(192 * kMB, unit * row));
              // Parallel: a block per worker whenever that fits in the bound.
              const std::size_t per_worker = static_cast<std::size_t>(workers) * block * row;
              if (per_worker <= 192 * kMB) {
                EXPECT_GE(rows, workers * block);
              }
              // Balanced: as many blocks for each worker.
              if (rows / block >= workers) {
                EXPECT_EQ(rows / block % workers, 0) << rows;
              }
            }
}

TEST(StripPlan, BigEnvironmentMapsOnTwoCores) {
  // 84 HALF channels (R, G, B + 81 bands), ZIP (16 rows), 2 workers: 4 blocks per write at
  // 4K (44 MB), 2 at 8K (64 MiB allows 3, but a third block would leave a worker waiting), 2 at
  // 16K (one per worker, 88 MB).
  const auto row = [](int width) { return static_cast<std::size_t>(width) * 84 * 2; };
  EXPECT_EQ(strip_rows(2048, 16, row(4096), 2), 64);
  EXPECT_EQ(strip_rows(4096, 16, row(8192), 2), 32);
  EXPECT_EQ(strip_rows(8192, 16, row(16384), 2), 32);
  // One worker: two blocks where they fit.
  EXPECT_EQ(strip_rows(2048, 16, row(4096), 1), 32);
  // A 1-row image: one row, not a block's worth of buffer.
  EXPECT_EQ(strip_rows(1, 16, row(65536), 2), 1);
}

}  // namespace
}  // namespace spectralize
