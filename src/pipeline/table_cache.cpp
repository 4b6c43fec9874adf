#include "pipeline/table_cache.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cinttypes>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "imagefile/safe_output.h"
#include "spectralize/core/error.h"
#include "text/strings.h"

namespace spectralize {

namespace {

constexpr char kMagic[16] = "SPECTRALIZE-TBL";  // 15 chars + NUL
constexpr std::uint32_t kFormatVersion = 4;     // 4: the standard FNV-1a checksum; 3: exact nodes
constexpr std::size_t kMaxKey = 4096;

// File layout: magic[16], u32 version, u64 key length, key, u64 bands, u64 entries, then per
// entry u64 node index, u8 feasible, bands floats if feasible; last a u64 FNV-1a checksum of
// everything before it. The largest file a table can have:
std::size_t max_file_size(const SpectralTable& t) {
  return sizeof kMagic + 4 + 8 + kMaxKey + 16 + t.node_count() * (9 + 4 * t.bands()) + 8;
}

}  // namespace

std::string table_cache_file(const std::string& dir, const std::string& key) {
  char name[64];
  std::snprintf(name, sizeof name, "spectralize-table-%016" PRIx64 ".bin", fnv1a(key));
  return (std::filesystem::path(dir) / name).string();
}

std::string load_table_cache(SpectralTable& table, const std::string& file,
                             const std::string& key) {
  const int fd = ::open(file.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return errno == ENOENT ? "" : std::string("cannot read: ") + std::strerror(errno);
  struct stat st = {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd);
    return S_ISDIR(st.st_mode) ? "is a directory" : "not a regular file";
  }
  if (static_cast<std::size_t>(st.st_size) > max_file_size(table)) {
    ::close(fd);
    return "too large for a node table (" + std::to_string(st.st_size) + " bytes)";
  }
  std::string bytes(static_cast<std::size_t>(st.st_size), '\0');
  std::size_t got = 0;
  while (got < bytes.size()) {
    const ssize_t n = ::read(fd, bytes.data() + got, bytes.size() - got);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    got += static_cast<std::size_t>(n);
  }
  ::close(fd);
  if (got != bytes.size()) return "cannot read it whole";
  if (bytes.size() < sizeof kMagic + 8 || std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0)
    return "not a spectralize node table";
  std::uint64_t stored_sum;
  std::memcpy(&stored_sum, bytes.data() + bytes.size() - 8, 8);
  if (fnv1a(std::string_view(bytes.data(), bytes.size() - 8)) != stored_sum)
    return "checksum mismatch (corrupt or truncated)";
  std::size_t at = sizeof kMagic;
  auto take = [&](void* dst, std::size_t n) {
    if (at + n > bytes.size() - 8) throw Error("truncated");
    std::memcpy(dst, bytes.data() + at, n);
    at += n;
  };
  try {
    std::uint32_t version;
    std::uint64_t key_len, bands, entries;
    take(&version, 4);
    if (version != kFormatVersion) return "table format version " + std::to_string(version);
    take(&key_len, 8);
    if (key_len > kMaxKey) return "bad key length";
    std::string stored_key(key_len, '\0');
    take(stored_key.data(), key_len);
    if (stored_key != key) return "made for other settings (" + clip(stored_key, 200) + ")";
    take(&bands, 8);
    take(&entries, 8);
    if (bands != table.bands() || entries > table.node_count()) return "inconsistent sizes";
    std::vector<float> values(table.bands());
    for (std::uint64_t e = 0; e < entries; ++e) {
      std::uint64_t index;
      std::uint8_t feasible;
      take(&index, 8);
      take(&feasible, 1);
      if (!feasible) return "node " + std::to_string(index) + " has no spectrum";
      take(values.data(), values.size() * sizeof(float));
      // Each node must reproduce its own colour: a valid checksum does not make spectra right.
      if (!table.adopt_node(index, std::span<const float>(values)))
        return "node " + std::to_string(index) +
               " is not the spectrum of its colour (a poisoned or foreign table)";
    }
  } catch (const Error&) {
    return "truncated";
  }
  return "";
}

std::string save_table_cache(const SpectralTable& table, const std::string& file,
                             const std::string& key) {
  std::string bytes(kMagic, sizeof kMagic);
  auto put = [&](const void* src, std::size_t n) {
    bytes.append(static_cast<const char*>(src), n);
  };
  const std::uint32_t version = kFormatVersion;
  const std::uint64_t key_len = key.size(), bands = table.bands();
  put(&version, 4);
  put(&key_len, 8);
  put(key.data(), key.size());
  put(&bands, 8);
  std::uint64_t entries = 0;
  const std::size_t entries_at = bytes.size();
  put(&entries, 8);
  table.for_each_node([&](std::size_t i, std::span<const float> values) {
    const std::uint64_t index = i;
    const std::uint8_t feasible = !values.empty();
    put(&index, 8);
    put(&feasible, 1);
    if (feasible) put(values.data(), values.size() * sizeof(float));
    ++entries;
  });
  std::memcpy(bytes.data() + entries_at, &entries, 8);
  const std::uint64_t sum = fnv1a(std::string_view(bytes.data(), bytes.size()));
  put(&sum, 8);
  try {
    // The cache folder is the user's; the file in it is named by spectralize, so a link there is
    // not followed.
    AtomicOutput out(file, WriteRules::named("a node cache file")
                               .below(std::filesystem::path(file).parent_path().string()));
    out.write(bytes);
    out.commit();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace spectralize
