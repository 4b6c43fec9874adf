#include "imagefile/strip_plan.h"

#include <algorithm>

namespace spectralize {

int strip_rows(int height, int block, std::size_t row_bytes, int workers) {
  block = std::max(1, block);
  const std::size_t block_bytes =
      std::max<std::size_t>(1, row_bytes * static_cast<std::size_t>(block));
  auto within = [&](std::size_t bytes) {
    return static_cast<int>(std::max<std::size_t>(1, bytes / block_bytes));
  };
  int blocks =
      std::max(std::min(2 * workers, within(64u << 20)), std::min(workers, within(192u << 20)));
  // A whole number of blocks per worker: with 3 blocks on 2 workers one of them waits a third
  // of every write.
  if (blocks > workers) blocks = blocks / workers * workers;
  return std::max(1, std::min(block * blocks, height));
}

}  // namespace spectralize
