// spectralize ingest SRC... -o DESTDIR: a texture library to spectral OpenEXR, with its
// progress, summary and manifest; --merge joins the manifests of a farm's shards.

#include <fmt/core.h>
#include <unistd.h>

#include <cstdlib>
#include <string>

#include "ingest/ingest.h"
#include "ingest/shard.h"
#include "pipeline/job_plan.h"
#include "spectralize/core/error.h"
#include "text/strings.h"
#include "tool/console.h"
#include "tool/options.h"

namespace spectralize::tool {

namespace {

void print_summary(const IngestSummary& s, bool merged) {
  const double mpx = static_cast<double>(s.pixels) / 1e6;
  std::string left;
  for (const auto& [kind, n] : s.left_out_by_reason)
    left += fmt::format("{}{} {}", left.empty() ? "" : ", ", n, kind);
  fmt::print(stderr,
             "spectralize ingest: {} files{}: {} converted, {} up to date, {} data skipped, {} "
             "data copied, {} derived from another, {} failed; {} left out{}{}; {:.1f} Mpixel in "
             "{:.1f} s ({:.2f} Mpixel/s, {:.1f} files/s); manifest '{}'\n",
             s.files(), merged ? " (all shards)" : "", s.converted, s.up_to_date, s.skipped_data,
             s.copied_data, s.derived, s.failed, s.left_out, left.empty() ? "" : " (" + left + ")",
             s.not_entered ? fmt::format(", {} not entered", s.not_entered) : "", mpx, s.seconds,
             s.seconds > 0 ? mpx / s.seconds : 0.0,
             s.seconds > 0 ? static_cast<double>(s.files()) / s.seconds : 0.0, s.manifest);
}

}  // namespace

int run_ingest_command(const Options& opt) {
  if (opt.output.empty()) throw UsageError{"ingest: -o DESTDIR is required"};
  if (opt.merge) {
    if (!opt.inputs.empty() || !opt.inputs_from.empty())
      throw UsageError{"ingest --merge takes only -o DESTDIR"};
    const IngestSummary s = merge_ingest_manifests(opt.output);
    if (opt.verbosity > 0) print_summary(s, true);
    return s.ok() ? kExitOk : kExitFailure;
  }
  IngestRequest request;
  request.sources = opt.inputs;
  request.inputs_from = opt.inputs_from;
  request.destination = opt.output;
  request.manifest = opt.manifest;
  request.force = opt.force;
  request.settings = opt.settings;
  if (request.sources.empty() && request.inputs_from.empty())
    throw UsageError{"ingest: give the files, folders or patterns to ingest (or --inputs-from)"};
  // The config and colour space are command-line values: checked before any work.
  const OptionNames names{"--", "-o"};
  JobPlan job = usage_checked("", [&] { return plan_to_spectral(request.settings, "", names); });
  request.settings = job.settings;
  const ShardSpec shard = usage_checked("", [&] {
    if (!opt.shard.empty()) return with_context("--shard", [&] { return parse_shard(opt.shard); });
    return slurm_shard().value_or(ShardSpec{});
  });
  request.shard = shard.index;
  request.shards = shard.count;
  const IngestPlan plan = usage_checked("", [&] { return plan_ingest(request, std::move(job)); });
  const LogFn log = console_log(opt.verbosity);
  if (opt.verbosity >= 2)
    log(1, fmt::format("ingest: {} files in this shard ({} of {}), {} in the batch; {} left out",
                       plan.items.size(), request.shard, request.shards, plan.all_items,
                       plan.left_out.size()));
  // What the walk left out: a failure to enter is an error, the rest is said at -v.
  for (const LeftOut& l : plan.left_out) {
    if (l.failure)
      fmt::print(stderr, "spectralize ERROR: '{}': {}\n", clip(l.path, 200), l.reason);
    else
      log(1, fmt::format("left out '{}': {}", clip(l.path, 200), l.reason));
  }
  const bool tty = ::isatty(STDERR_FILENO) != 0;
  IngestProgressFn progress = [&](std::uint64_t done, std::uint64_t total,
                                  const std::string& news) {
    // A file that failed is an error on stderr, whatever the verbosity; the batch goes on.
    if (news.rfind("failed: ", 0) == 0)
      fmt::print(stderr, "{}spectralize ERROR: {}\n", tty && opt.verbosity > 0 ? "\n" : "",
                 news.substr(8));
    if (opt.verbosity == 0) return;
    if (tty) {
      const int filled = static_cast<int>(30.0 * done / std::max<std::uint64_t>(1, total));
      fmt::print(stderr, "\r[{:<30}] {}/{} files ", std::string(filled, '#'), done, total);
      if (done == total) fmt::print(stderr, "\n");
    } else if (opt.verbosity >= 2) {
      fmt::print(stderr, "spectralize ingest: {}/{} {}\n", done, total, news);
    }
  };
  const IngestSummary s = run_ingest(plan, progress, log);
  if (opt.verbosity > 0) print_summary(s, false);
  return s.ok() ? kExitOk : kExitFailure;
}

}  // namespace spectralize::tool
