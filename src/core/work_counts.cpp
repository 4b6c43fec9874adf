#include "core/work_counts.h"

#include <atomic>

namespace spectralize {

namespace {

std::atomic<std::uint64_t> g_counts[4];

}  // namespace

WorkCounts WorkCounts::since(const WorkCounts& earlier) const {
  return {configs_parsed - earlier.configs_parsed,
          spectralizers_built - earlier.spectralizers_built,
          file_rule_matches - earlier.file_rule_matches, inputs_opened - earlier.inputs_opened};
}

void count_work(Work work) {
  g_counts[static_cast<int>(work)].fetch_add(1, std::memory_order_relaxed);
}

WorkCounts work_counts() {
  auto get = [](Work w) { return g_counts[static_cast<int>(w)].load(std::memory_order_relaxed); };
  return {get(Work::config_parsed), get(Work::spectralizer_built), get(Work::file_rule_match),
          get(Work::input_opened)};
}

}  // namespace spectralize
