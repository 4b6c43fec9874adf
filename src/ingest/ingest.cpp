#include "ingest/ingest.h"

#include <OpenImageIO/imageio.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cinttypes>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <thread>

#include "classify/input_interpretation.h"
#include "colour/colour_space.h"
#include "imagefile/exr_header.h"
#include "imagefile/image_reader.h"
#include "imagefile/safe_output.h"
#include "ingest/ingest_manifest.h"
#include "pipeline/image_conversion.h"
#include "pipeline/image_job.h"
#include "pipeline/image_report.h"
#include "pipeline/table_pool.h"
#include "settings/map_kind.h"
#include "spectralize/core/error.h"
#include "spectralize/version.h"
#include "text/json_text.h"
#include "text/strings.h"

namespace fs = std::filesystem;

namespace spectralize {

namespace {

using Json = nlohmann::ordered_json;
using Clock = std::chrono::steady_clock;

constexpr const char* kKeyAttribute = "spectralize:ingestKey";
constexpr const char* kRequestKeyAttribute = "spectralize:ingestRequest";

// What identifies an output's input apart from the settings: the version, the input by its
// place in its source tree (what the output mirrors: the same on every machine that mounts the
// library elsewhere), its size and modification time, and the config by its content.
std::string key_prefix(const IngestItem& item, const struct stat& st, const std::string& config) {
  return "spectralize " SPECTRALIZE_VERSION "|" + item.source_relative + "|" +
         std::to_string(st.st_size) + "|" + std::to_string(st.st_mtim.tv_sec) + "." +
         std::to_string(st.st_mtim.tv_nsec) + "|" + config;
}

// The up-to-date key: the prefix and every setting that shapes the file, as resolved for it
// (its colour space and mode as interpret_colour and decide_light_or_surface decided them, by
// the name table in force), from the same list its header records (file_settings). So a
// changed name table or rule redoes exactly the files it decides otherwise; one that only
// restates a decision (--colorspace naming the space a file was decided in) keeps the file.
std::string ingest_key(const std::string& prefix, const Settings& resolved) {
  std::string text = prefix;
  for (const auto& [spec, value] : file_settings(resolved))
    text.append("|").append(spec->key).append("=").append(value);
  return hex64(fnv1a(text));
}

// A memo of the key: everything the decisions and the conversion are made from, as asked (the
// input as spelt, every setting that is not how the batch runs), so that a rerun of the same
// request finds an output up to date from its header alone. When it differs, the input is
// decided again and the key of the settings as resolved says (docs/DESIGN.md §12).
std::string request_key(const std::string& prefix, const IngestItem& item) {
  std::string text = prefix + "|" + item.input;
  // Every value as given (format(), not setting_value()): the mode asked, not resolved, and
  // settings whose relevance only the resolution decides (the illuminant of a reflectance).
  for (const SettingSpec& spec : settings_schema())
    if (spec.applies(kIngest) && spec.key != "threads" && spec.key != "jobs" && spec.key != "cache")
      text.append("|").append(spec.key).append("=").append(spec.format(item.settings));
  return hex64(fnv1a(text));
}

// The up-to-date record of an output, from what its header recorded: how it was decided and
// what its conversion warned about.
void recorded_decision(Json& r, ExrHeaderValues& recorded, const std::string& input,
                       const OptionNames& names) {
  r["colorspace"] = recorded.strings["spectralize:colorspace"];
  r["colorspace_reason"] = recorded.strings["spectralize:colorspaceReason"];
  r.update(identity_record(identity_from_attributes(recorded.strings)));
  r["mode"] = recorded.strings["spectralize:mode"];
  r["mode_reason"] = recorded.strings["spectralize:modeReason"];
  const std::vector<std::string> warnings =
      recorded_warnings(recorded.strings, recorded.doubles, input, names);
  if (!warnings.empty()) r["warnings"] = warnings;
}

// A byte-for-byte copy through an AtomicOutput, with the input's modification time (so a rerun
// can tell it is up to date).
void copy_checked(const std::string& input, const std::string& output, const struct stat& st,
                  const WriteRules& rules) {
  check_readable_file(input, "input");
  AtomicOutput out(output, rules, std::span<const std::string>(&input, 1));
  std::ifstream in(input, std::ios::binary);
  std::vector<char> buf(1 << 20);
  while (in) {
    in.read(buf.data(), static_cast<std::streamsize>(buf.size()));
    if (in.gcount() > 0)
      out.write(std::string_view(buf.data(), static_cast<std::size_t>(in.gcount())));
  }
  if (in.bad()) throw FileError(quoted_path(input) + ": cannot read it whole");
  out.commit();
  const struct timespec times[2] = {st.st_atim, st.st_mtim};
  ::utimensat(AT_FDCWD, output.c_str(), times, 0);
}

bool same_copy(const std::string& output, const struct stat& in) {
  struct stat st = {};
  return ::stat(output.c_str(), &st) == 0 && S_ISREG(st.st_mode) && st.st_size == in.st_size &&
         st.st_mtim.tv_sec == in.st_mtim.tv_sec && st.st_mtim.tv_nsec == in.st_mtim.tv_nsec;
}

}  // namespace

namespace {

// Thrown through a conversion when the batch is asked to stop.
struct Interrupted : std::exception {
  const char* what() const noexcept override { return "interrupted"; }
};

// What every file of a batch shares.
struct Batch {
  const IngestPlan& plan;
  const LogFn& log;
  ThreadShare share;  // the batch's cores, split between the files converting now
  TablePool pool;
  std::atomic<std::uint64_t> stale{0};
  std::mutex swept_mutex{};
  std::set<std::string> swept{};            // output folders already cleared of stale temporaries
  const std::atomic<bool>* stop = nullptr;  // asked to stop (may be null)
  bool stopping() const { return stop && stop->load(); }

  /// Removes, once per folder, the temporaries killed earlier runs left there (any file's:
  /// outputs, copies, manifests; a live writer's are locked and stay). Cost: one listing.
  void sweep(const std::string& folder) {
    std::lock_guard<std::mutex> lock(swept_mutex);
    if (swept.insert(folder).second) stale += remove_stale_temporaries(folder);
  }
};

// The fields of a converted file's record, as its report has them (pipeline/image_report.h),
// in the manifest's order; "warnings" follows when there are any.
constexpr std::array<const char*, 11> kConvertedFields{"colorspace",
                                                       "colorspace_reason",
                                                       "colorspace_interop_id",
                                                       "colorspace_interop_id_source",
                                                       "colorspace_encoding",
                                                       "mode",
                                                       "mode_reason",
                                                       "pixels",
                                                       "out_of_gamut_pixels",
                                                       "invalid_pixels",
                                                       "max_relative_xyz_error"};

// One file of a batch, taken through its steps in order: its source is converted (derived),
// non-colour data (skipped or copied), up to date, converted, or failed. Each step that
// settles the file returns its record.
class FileIngest {
 public:
  FileIngest(const IngestItem& item, Batch& batch) : item_(item), batch_(batch) {
    put_path(r_, "input", item.input);
    if (!item.output.empty()) put_path(r_, "output", item.output);
    if (!item.origin.empty()) r_["origin"] = Json::parse(item.origin);
  }

  /// The file's record; null when the batch was asked to stop during its conversion (not done:
  /// a rerun does it). Cost: the file's conversion or copy, or reading its output's header.
  Json run() {
    try {
      if (!item_.failure.empty()) throw Error(item_.failure);
      if (!item_.derived_from.empty()) {  // its source is converted (same_stem.h)
        put_path(r_, "source", item_.derived_from);
        r_["reason"] = utf8_escaped(item_.note);
        return finish("derived");
      }
      if (!item_.note.empty()) r_["note"] = utf8_escaped(item_.note);
      check_readable_file(item_.input, "input");
      ::stat(item_.input.c_str(), &st_);
      make_output_folder();
      // By the words of its name and folders (map_kind.h), before the file is read; a list
      // line that states what the file is (a stage's declaration) is followed instead.
      const Settings& s = item_.settings;
      const NameVerdict name =
          s.stated_for_file
              ? NameVerdict{}
              : map_kind_by_name(item_.input, name_words_in_force(s.data_names, s.colour_names));
      if (name.kind == MapKind::data) {
        if (!name.warnings.empty()) r_["warnings"] = name.warnings;
        return as_data("data by its " + name.reason);
      }
      // The same request as made the output: up to date from its header alone.
      const std::string prefix = key_prefix(item_, st_, batch_.plan.config_identity);
      const std::string asked = request_key(prefix, item_);
      ExrHeaderValues recorded;
      if (!force()) {
        recorded = exr_header_values(item_.output);
        if (!recorded.strings[kKeyAttribute].empty() &&
            recorded.strings[kRequestKeyAttribute] == asked)
          return up_to_date(recorded);
      }
      JobPlan file_plan = batch_.plan.job;
      file_plan.settings = s;
      // A space its list line names, resolved and checked as the command line's are.
      resolve_colour_spaces(file_plan);
      if (const std::string data_reason = decide(file_plan); !data_reason.empty())
        return as_data(data_reason);
      // Up to date: the key recorded in the output's header, of the settings as resolved.
      if (!force() && recorded.strings[kKeyAttribute] == ingest_key(prefix, file_plan.settings))
        return up_to_date(recorded);
      return convert(file_plan, prefix, asked);
    } catch (const Interrupted&) {
      return Json();
    } catch (const std::exception& e) {
      // Where the file comes from, when its list line says (a USD stage's prim).
      std::string where;
      if (r_.contains("origin") && r_["origin"].contains("where"))
        where = " (" + r_["origin"]["where"].get<std::string>() + ")";
      return finish("failed", e.what() + where);
    }
  }

 private:
  bool force() const { return batch_.plan.request.force; }
  const std::string& destination() const { return batch_.plan.request.destination; }

  Json finish(const std::string& status, const std::string& message = "") {
    r_["status"] = status;
    if (!message.empty()) r_["message"] = utf8_escaped(message);
    r_["seconds"] = std::chrono::duration<double>(Clock::now() - start_).count();
    return r_;
  }

  void make_output_folder() {
    const fs::path out(item_.output);
    std::error_code ec;
    fs::create_directories(out.parent_path(), ec);
    if (!fs::is_directory(out.parent_path(), ec))
      throw FileError(quoted_path(item_.output) + ": cannot create the folder " +
                      quoted_path(out.parent_path().string()) +
                      (ec ? ": " + ec.message() : std::string()));
    batch_.sweep(out.parent_path().string());
  }

  // Non-colour data: skipped, or copied byte for byte; never spectralized.
  Json as_data(const std::string& reason) {
    r_["reason"] = utf8_escaped(reason);
    r_.erase("output");
    r_.erase("output_base64");
    if (!item_.settings.ingest.copy_data) return finish("skipped_data");
    if (!item_.copy_failure.empty()) throw FileError(item_.copy_failure);
    put_path(r_, "output", item_.copy);
    if (!force() && same_copy(item_.copy, st_)) return finish("up_to_date");
    copy_checked(item_.input, item_.copy, st_,
                 WriteRules::named("the copy of " + quoted_path(item_.input))
                     .below(destination())
                     .folder_synced_by_caller());
    return finish("copied_data");
  }

  // How the output was decided and what its conversion warned about, from its header.
  Json up_to_date(ExrHeaderValues& recorded) {
    recorded_decision(r_, recorded, item_.input, batch_.plan.request.names);
    return finish("up_to_date");
  }

  // Decided once (docs/DESIGN.md §9): data by an ambiguous word settled by the channels or by a
  // data colour space (the reason returned); else light or surface, into `plan` with the
  // settings as resolved for this file, which decide whether its output is up to date as they
  // decide what the conversion writes into the header. The conversion takes this decision.
  std::string decide(JobPlan& plan) {
    const ImageReader& reader =
        reader_.emplace(item_.input, spectral_output_channels(plan.settings), true);
    const InputInterpretation in =
        interpret_colour(item_.input, reader.spec(), plan.settings, plan.colour_spaces());
    if (!in.contradiction.empty()) r_["contradiction"] = utf8_escaped(in.contradiction);
    if (!in.data_reason.empty()) {
      if (!in.warnings.empty()) r_["warnings"] = in.warnings;
      return in.data_reason;
    }
    plan = planned_input(plan, item_.input, reader.spec(), &in);
    return "";
  }

  Json convert(const JobPlan& plan, const std::string& prefix, const std::string& asked) {
    ImageJobOptions options;
    options.shared.pool = &batch_.pool;
    options.reader = &*reader_;  // opened by decide(): each input is opened once
    options.shared.share = &batch_.share;
    options.output = WriteRules::named("the output of " + quoted_path(item_.input))
                         .below(destination())
                         .folder_synced_by_caller();
    options.shared.attributes = [&](const Settings& resolved) {
      return std::map<std::string, std::string>{{kKeyAttribute, ingest_key(prefix, resolved)},
                                                {kRequestKeyAttribute, asked},
                                                {"spectralize:source", item_.input}};
    };
    const ThreadShare::Running running(batch_.share);
    r_["threads"] = batch_.share.now();  // at its start; files finishing give theirs later
    // Between strips: a stop request abandons the conversion (its temporary is removed).
    const ProgressFn check_stop = [this](std::uint64_t, std::uint64_t) {
      if (batch_.stopping()) throw Interrupted();
    };
    const Json report = report_record(
        run_image_job(plan, item_.input, item_.output, check_stop, batch_.log, options));
    for (const char* field : kConvertedFields) r_[field] = report.at(field);
    if (!report.at("warnings").empty()) r_["warnings"] = report.at("warnings");
    return finish("converted");
  }

  const IngestItem& item_;
  Batch& batch_;
  const Clock::time_point start_ = Clock::now();
  std::optional<ImageReader> reader_;  // the input, opened to decide it and read to convert it
  Json r_;
  struct stat st_ = {};
};

}  // namespace

IngestSummary run_ingest(const IngestPlan& plan, const IngestProgressFn& progress, const LogFn& log,
                         const std::atomic<bool>* stop) {
  install_cleanup_handlers();
  const ReadFileScope reads;  // the run's registry: what it reads, what it writes
  const auto t0 = Clock::now();
  const WorkCounts work_before = work_counts();
  const Settings& base = plan.request.settings;
  const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const int total_threads = base.threads > 0 ? base.threads : cores;
  const int files = static_cast<int>(std::max<std::size_t>(1, plan.items.size()));
  const int jobs = std::max(1, std::min(base.ingest.jobs > 0 ? base.ingest.jobs : cores, files));
  OIIO::attribute("threads", total_threads);
  OIIO::attribute("exr_threads", total_threads);
  std::error_code ec;
  fs::create_directories(plan.request.destination, ec);
  // The planned files into the registry: every AtomicOutput of the batch is checked against all
  // of them, not only against what was written so far.
  plan.files.claim();
  Batch batch{plan, log, ThreadShare(total_threads), {}, {}, {}, {}};
  batch.stop = stop;
  // The manifest's place is checked (and its temporary file made) before any work; a killed
  // earlier run's temporary manifest goes (unless the manifest is a stream).
  const fs::path manifest_path(plan.manifest);
  if (!fs::exists(manifest_path, ec) || fs::is_regular_file(manifest_path, ec))
    batch.sweep(manifest_path.has_parent_path() ? manifest_path.parent_path().string() : ".");
  AtomicOutput manifest(
      plan.manifest,
      WriteRules::named("the manifest")
          .streams()
          .below(plan.request.manifest.empty() ? plan.request.destination : std::string()));

  std::vector<Json> records(plan.items.size());
  IngestSummary sum;
  std::mutex mutex;
  std::atomic<std::size_t> next{0};
  std::size_t done = 0;
  auto worker = [&] {
    ensure_signal_stack();  // a crash on this thread still removes the batch's temporaries
    for (std::size_t i; (i = next.fetch_add(1)) < plan.items.size();) {
      if (batch.stopping()) break;
      Json r = FileIngest(plan.items[i], batch).run();
      std::lock_guard<std::mutex> lock(mutex);
      if (r.is_null()) continue;  // interrupted
      const std::string status = r["status"];
      if (status == "converted") ++sum.converted, sum.pixels += r["pixels"].get<std::uint64_t>();
      if (status == "up_to_date") ++sum.up_to_date;
      if (status == "skipped_data") ++sum.skipped_data;
      if (status == "copied_data") ++sum.copied_data;
      if (status == "derived") ++sum.derived;
      if (status == "failed") ++sum.failed;
      if (progress)
        progress(++done, plan.items.size(),
                 status == "failed" ? "failed: " + r["message"].get<std::string>()
                                    : status + " " + plan.items[i].input);
      records[i] = std::move(r);
    }
  };
  std::vector<std::thread> threads;
  for (int j = 1; j < jobs; ++j) threads.emplace_back(worker);
  worker();
  for (auto& t : threads) t.join();
  for (const std::string& w : batch.pool.save()) log(0, w);
  // The renames of the batch made durable, one sync per output folder, before the manifest
  // says they happened.
  for (const std::string& folder : batch.swept) sync_folder(folder);

  for (const LeftOut& l : plan.left_out) {
    ++sum.left_out;
    ++sum.left_out_by_reason[l.kind];
    if (l.failure) ++sum.not_entered;
  }
  sum.stale_temporaries_removed = batch.stale;
  sum.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  sum.work = work_counts().since(work_before);
  sum.manifest = plan.manifest;
  sum.interrupted = batch.stopping();
  std::string text;
  for (const Json& r : records) {
    if (r.is_null()) {
      ++sum.not_done;  // not started, or abandoned by the interruption
      continue;
    }
    text += dump_json(r) + "\n";
    // Kept for callers that cannot read the manifest back (a stream, /dev/stdout).
    if (r.value("status", "") == "failed") sum.failures.push_back(dump_json(r));
  }
  sum.interrupted = sum.interrupted && sum.not_done > 0;
  for (const LeftOut& l : plan.left_out) text += left_out_line(l) + "\n";
  text +=
      summary_line(
          sum, PartInfo{plan.batch, {plan.request.shard, plan.request.shards}, plan.all_items}) +
      "\n";
  manifest.write(text);
  manifest.commit();
  return sum;
}

}  // namespace spectralize
