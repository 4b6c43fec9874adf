#pragma once
// Shards of an ingest batch (docs/DESIGN.md §12): the one parser and validation of "I/N" specs,
// of Slurm's array variables and of the manifest parts' names, shared by the CLI, the Python
// module and --merge, so that each refuses what the others refuse.

#include <cstdlib>
#include <functional>
#include <optional>
#include <string>
#include <string_view>

namespace spectralize {

/// Shard `index` (0-based) of `count`.
struct ShardSpec {
  int index = 0, count = 1;
  bool operator==(const ShardSpec&) const = default;
};

/// The most shards a batch splits into.
inline constexpr int kMaxShards = 1000000;

/// Parses "I/N": two whole decimal numbers (digits only: no sign, exponent, spaces or leading
/// zeros) with 0 <= I < N <= kMaxShards. Throws Error "'<text>': <why> (expected I/N, shard I of
/// N with 0 <= I < N)". Cost: O(length).
ShardSpec parse_shard(std::string_view text);

/// The shard of a Slurm array task, from SLURM_ARRAY_TASK_ID, _MIN, _MAX, _STEP and _COUNT (as
/// `getenv` gives them): the task's position in the array, (ID - MIN) / STEP, of COUNT. Nullopt
/// outside an array task (no SLURM_ARRAY_TASK_ID). Throws Error naming the variable for a value
/// that is not a whole number, an array whose indices are not MIN, MIN + STEP, ... (a list such
/// as --array=1,2,7: give --shard) or a task outside it. Cost: O(1).
std::optional<ShardSpec> slurm_shard(const std::function<const char*(const char*)>& getenv =
                                         [](const char* name) {
                                           return static_cast<const char*>(std::getenv(name));
                                         });

/// "spectralize-ingest.part-I-of-N.jsonl", the manifest of one shard. Cost: O(1).
std::string part_name(const ShardSpec& shard);

/// The shard a manifest part's file name names: nullopt for a name that does not start with
/// "spectralize-ingest.part-"; throws Error naming the file for one that does but is not exactly
/// part_name of a valid shard ("part-5-of-2", "part-01-of-2", an index too big). Cost: O(name).
std::optional<ShardSpec> parse_part_name(std::string_view name);

}  // namespace spectralize
