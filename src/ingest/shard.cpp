#include "ingest/shard.h"

#include <charconv>
#include <cstdint>
#include <cstdlib>

#include "spectralize/core/error.h"

namespace spectralize {

namespace {

constexpr std::string_view kPartPrefix = "spectralize-ingest.part-";
constexpr std::string_view kPartSuffix = ".jsonl";

// A whole decimal number of digits only, without leading zeros, at most `max`; nullopt
// otherwise. Never overflows.
std::optional<std::uint64_t> whole(std::string_view t, std::uint64_t max) {
  if (t.empty() || t.size() > 19 || (t.size() > 1 && t[0] == '0')) return std::nullopt;
  for (char c : t)
    if (c < '0' || c > '9') return std::nullopt;
  std::uint64_t v = 0;
  std::from_chars(t.data(), t.data() + t.size(), v);
  if (v > max) return std::nullopt;
  return v;
}

// The pair I, N of "I<sep>N", checked; `why` says what is wrong, else "".
std::optional<ShardSpec> shard_of(std::string_view text, std::string_view sep, std::string& why) {
  const std::size_t at = text.find(sep);
  if (at == std::string_view::npos) {
    why = "no '" + std::string(sep) + "'";
    return std::nullopt;
  }
  const std::string_view i = text.substr(0, at), n = text.substr(at + sep.size());
  const auto index = whole(i, kMaxShards), count = whole(n, kMaxShards);
  if (!count || *count == 0) {
    why = quote(n, 40) + " is not a shard count from 1 to " + std::to_string(kMaxShards);
    return std::nullopt;
  }
  if (!index) {
    const bool digits = !i.empty() && i.find_first_not_of("0123456789") == std::string_view::npos;
    why = quote(i, 40) + (digits && i[0] != '0'
                              ? " is more than the most shards, " + std::to_string(kMaxShards)
                              : std::string(" is not a whole number (digits "
                                            "only, without leading zeros)"));
    return std::nullopt;
  }
  if (*index >= *count) {
    why = "shard " + std::to_string(*index) + " does not exist in " + std::to_string(*count) +
          " (they are 0.." + std::to_string(*count - 1) + ")";
    return std::nullopt;
  }
  return ShardSpec{static_cast<int>(*index), static_cast<int>(*count)};
}

}  // namespace

ShardSpec parse_shard(std::string_view text) {
  std::string why;
  if (auto s = shard_of(text, "/", why)) return *s;
  throw Error(quote(text) + ": " + why + " (expected I/N, shard I of N with 0 <= I < N)");
}

std::optional<ShardSpec> slurm_shard(const std::function<const char*(const char*)>& getenv) {
  const char* id = getenv("SLURM_ARRAY_TASK_ID");
  if (!id) return std::nullopt;
  // Each variable a whole number; the ones Slurm always sets for an array task are required.
  auto number = [&](const char* name, bool required, std::uint64_t fallback) -> std::uint64_t {
    const char* v = getenv(name);
    if (!v) {
      if (required)
        throw Error(std::string("SLURM_ARRAY_TASK_ID is set but ") + name +
                    " is not: give --shard I/N");
      return fallback;
    }
    const auto n = whole(v, 4000000000ull);
    if (!n)
      throw Error(std::string(name) + "=" + quote(v) +
                  ": not a whole number (a Slurm array task sets it); give --shard I/N");
    return *n;
  };
  const std::uint64_t task = number("SLURM_ARRAY_TASK_ID", true, 0);
  const std::uint64_t count = number("SLURM_ARRAY_TASK_COUNT", true, 0);
  const std::uint64_t min = number("SLURM_ARRAY_TASK_MIN", false, 0);
  const std::uint64_t step = number("SLURM_ARRAY_TASK_STEP", false, 1);
  const std::uint64_t max =
      number("SLURM_ARRAY_TASK_MAX", false, min + (count > 0 ? count - 1 : 0) * step);
  const std::string array = "the Slurm array (SLURM_ARRAY_TASK_MIN " + std::to_string(min) +
                            ", _MAX " + std::to_string(max) + ", _STEP " + std::to_string(step) +
                            ", _COUNT " + std::to_string(count) + ")";
  if (count == 0 || count > static_cast<std::uint64_t>(kMaxShards) || step == 0)
    throw Error(array + " has no usable task count or step; give --shard I/N");
  // The tasks must be MIN, MIN + STEP, ..., MAX: a list such as --array=1,2,7 has no position
  // by arithmetic.
  if (max < min || (max - min) % step != 0 || (max - min) / step + 1 != count)
    throw Error(array + " is not MIN, MIN + STEP, ..., MAX with COUNT tasks (an --array list?): " +
                "give --shard I/N to each task");
  if (task < min || task > max || (task - min) % step != 0)
    throw Error("SLURM_ARRAY_TASK_ID " + std::to_string(task) + " is not a task of " + array);
  return ShardSpec{static_cast<int>((task - min) / step), static_cast<int>(count)};
}

std::string part_name(const ShardSpec& shard) {
  return std::string(kPartPrefix) + std::to_string(shard.index) + "-of-" +
         std::to_string(shard.count) + std::string(kPartSuffix);
}

std::optional<ShardSpec> parse_part_name(std::string_view name) {
  if (name.substr(0, kPartPrefix.size()) != kPartPrefix) return std::nullopt;
  std::string why = "does not end in " + std::string(kPartSuffix);
  std::optional<ShardSpec> s;
  if (name.size() > kPartPrefix.size() + kPartSuffix.size() &&
      name.substr(name.size() - kPartSuffix.size()) == kPartSuffix)
    s = shard_of(
        name.substr(kPartPrefix.size(), name.size() - kPartPrefix.size() - kPartSuffix.size()),
        "-of-", why);
  if (!s)
    throw Error(quote(name) + " is not the name of a manifest part (" + why +
                "; parts are spectralize-ingest.part-I-of-N.jsonl with 0 <= I < N)");
  return s;
}

}  // namespace spectralize
