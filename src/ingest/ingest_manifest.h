#pragma once
// The records of an ingest manifest (docs/DESIGN.md §12) shared by the batch and the merge of
// its shards: left-out records and the summary, with the identity of the part it closes.

#include <cstdint>
#include <string>

#include "ingest/ingest.h"
#include "ingest/shard.h"

namespace spectralize {

/// What a part of a batch is: the batch's identity, which shard, and how many files the whole
/// batch has.
struct PartInfo {
  std::string batch;
  ShardSpec shard;
  std::uint64_t batch_files = 0;
  bool merged = false;  // the merge of all the parts (shard is then {0, N})
};

/// The summary record, one JSON line: {"summary": {files, converted, ..., left_out,
/// not_entered, left_out_by_reason, seconds, batch, shard, shards, batch_files}}. Cost: O(1).
std::string summary_line(const IngestSummary& summary, const PartInfo& part);

/// A record of what the walk left out, one JSON line: {"left_out": path, "reason", "kind",
/// "failure"} (names as json_text.h writes them). Cost: O(1).
std::string left_out_line(const LeftOut& left);

}  // namespace spectralize
