#include "io/strip_plan.h"

#include <algorithm>
#include <numeric>

namespace spectralize {

int strip_rows(int height, int block, int input_tile, std::size_t row_bytes, int workers) {
  int unit = std::lcm(block, std::max(1, input_tile));
  if (unit > 512) unit = std::max(block, input_tile);
  const std::size_t unit_bytes =
      std::max<std::size_t>(1, row_bytes * static_cast<std::size_t>(unit));
  auto units_for = [&](int blocks) { return std::max(1, (blocks * block + unit - 1) / unit); };
  auto units_within = [&](std::size_t bytes) {
    return static_cast<int>(std::max<std::size_t>(1, bytes / unit_bytes));
  };
  const int units = std::max(std::min(units_for(2 * workers), units_within(64u << 20)),
                             std::min(units_for(workers), units_within(192u << 20)));
  return std::max(1, std::min(unit * units, height));
}

}  // namespace spectralize
