#pragma once
// Work that a batch must do once, not once per file, counted where it happens (docs/guide/
// ingest.md, "What a file costs beyond its conversion"): the ingest summary reports what its
// conversions took, and tests check the counts instead of timing the batch.

#include <cstdint>

namespace spectralize {

/// What this process has done so far of each kind (or, as a difference, a part of it).
struct WorkCounts {
  std::uint64_t configs_parsed = 0;       // OCIO configs parsed (not served from the process's)
  std::uint64_t spectralizers_built = 0;  // spectralizers built (their models' setup included)
  std::uint64_t file_rule_matches = 0;    // paths OCIO's file rules were asked about
  std::uint64_t inputs_opened = 0;        // input images opened (their headers read)
  /// The work done between `earlier` and this. Cost: O(1).
  WorkCounts since(const WorkCounts& earlier) const;
};

enum class Work { config_parsed, spectralizer_built, file_rule_match, input_opened };

/// Counts one piece of work (thread-safe). Cost: one relaxed atomic add.
void count_work(Work work);

/// The counts so far. Cost: O(1).
WorkCounts work_counts();

}  // namespace spectralize
