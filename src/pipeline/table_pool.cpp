#include "pipeline/table_pool.h"

#include <filesystem>
#include <future>

#include <fmt/format.h>

#include "pipeline/table_cache.h"

namespace fs = std::filesystem;

namespace spectralize {

TablePool::Entry& TablePool::get(const Settings& s, const Mat3& frame, const LogFn& log,
                                 const std::string& cache_option) {
  // The table's layout follows from the same settings and the frame: they find the entry again
  // without building a spectralizer.
  std::string seen = table_cache_key(s, "") + "; method " +
                     (s.method == SpectralTable::Method::exact ? "exact" : "table") + "; cache " +
                     s.cache_dir + "; frame";
  for (double v : frame) seen += fmt::format(" {}", v);  // shortest round-trip form
  // The first file of a kind builds its entry; files of the same kind arriving meanwhile (a
  // batch's jobs start together) wait for it instead of building another spectralizer.
  std::promise<Entry*> building;
  std::shared_future<Entry*> built_by_another;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (auto it = seen_.find(seen); it != seen_.end()) return *it->second;
    if (auto it = building_.find(seen); it != building_.end())
      built_by_another = it->second;
    else
      building_.emplace(seen, building.get_future().share());
  }
  if (built_by_another.valid()) return *built_by_another.get();  // its failure is thrown here too
  try {
    Entry& entry = build(s, frame, log, cache_option, seen);
    building.set_value(&entry);
    return entry;
  } catch (...) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      building_.erase(seen);  // a later file tries again
    }
    building.set_exception(std::current_exception());
    throw;
  }
}

TablePool::Entry& TablePool::build(const Settings& s, const Mat3& frame, const LogFn& log,
                                   const std::string& cache_option, const std::string& seen) {
  // The key names everything the node spectra depend on (and the method: exact tables differ).
  auto spectralizer = std::make_unique<Spectralizer>(s.spectral);
  auto table = std::make_unique<SpectralTable>(*spectralizer, s.method, frame);
  const std::string key = table_cache_key(s, table->layout()) +
                          (s.method == SpectralTable::Method::exact ? "; exact" : "");
  // One entry per cache folder too: a table made without a folder (or for another one) must not
  // stand in for settings that ask for one, or that folder is never loaded nor saved.
  const std::string entry_key =
      key + (s.method == SpectralTable::Method::table ? "; cache " + s.cache_dir : "");
  std::lock_guard<std::mutex> lock(mutex_);
  building_.erase(seen);  // from now on seen_ has it
  auto it = entries_.find(entry_key);
  if (it != entries_.end()) {
    seen_[seen] = it->second.get();
    return *it->second;
  }
  auto entry = std::make_unique<Entry>();
  entry->key = key;
  entry->spectralizer = std::move(spectralizer);
  entry->table = std::move(table);
  if (!s.cache_dir.empty() && s.method == SpectralTable::Method::table) {
    std::error_code ec;
    fs::create_directories(s.cache_dir, ec);
    if (fs::is_directory(s.cache_dir, ec)) {
      entry->file_key = table_cache_key(s, entry->table->layout());
      entry->cache_file = table_cache_file(s.cache_dir, entry->file_key);
      const std::string why = load_table_cache(*entry->table, entry->cache_file, entry->file_key);
      entry->cache_status = why.empty()
                                ? (entry->table->stats().nodes_loaded > 0 ? "loaded" : "new")
                                : "rebuilt: " + why;
      if (!why.empty()) log(0, "cache '" + entry->cache_file + "' ignored and rebuilt: " + why);
    } else {
      log(0, cache_option + " '" + s.cache_dir +
                 "': not a folder that can be created; running without a persistent cache");
    }
  }
  Entry& ref = *entry;
  entries_[entry_key] = std::move(entry);
  seen_[seen] = &ref;
  return ref;
}

std::vector<std::string> TablePool::save() {
  std::vector<std::string> warnings;
  std::lock_guard<std::mutex> lock(mutex_);
  for (auto& [key, e] : entries_) {
    const std::uint64_t computed = e->table->stats().nodes_computed;
    if (e->cache_file.empty() || computed == e->saved_computed) continue;
    // Nodes another process saved meanwhile are adopted first (each is checked), so the file
    // grows by what both computed instead of keeping the last writer's only.
    (void)load_table_cache(*e->table, e->cache_file, e->file_key);
    const std::string why = save_table_cache(*e->table, e->cache_file, e->file_key);
    if (!why.empty())
      warnings.push_back("cache '" + e->cache_file + "' not saved: " + why);
    else
      e->saved_computed = computed;
  }
  return warnings;
}

}  // namespace spectralize
