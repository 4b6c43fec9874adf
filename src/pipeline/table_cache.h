#pragma once
// The persistent node cache of a SpectralTable (docs/DESIGN.md §4): one file per key in the
// cache folder, named by a stable 64-bit FNV-1a hash of the key, written atomically, read
// defensively (a regular file of bounded size, magic, version, key, checksum), and every stored
// node checked against its own colour before it is used. Anything unusable is reported and
// rebuilt, never trusted.

#include <string>

#include "core/tables/spectral_table.h"

namespace spectralize {

/// The cache file for `key` in `dir`: "<dir>/spectralize-table-<16 hex digits>.bin", the same
/// on every platform and standard library. Cost: O(key).
std::string table_cache_file(const std::string& dir, const std::string& key);

/// Loads the nodes of `file` into `table` if the file holds a table for `key` whose checksum and
/// nodes are intact. Returns "" when loaded or when the file does not exist yet, else why it was
/// rejected (nothing is then loaded). Never blocks (FIFOs, devices are refused).
/// Cost: O(file size).
std::string load_table_cache(SpectralTable& table, const std::string& file, const std::string& key);

/// Writes the computed nodes of `table` to `file` for `key`, atomically. Returns "" or why it
/// failed. Cost: O(nodes x bands).
std::string save_table_cache(const SpectralTable& table, const std::string& file,
                             const std::string& key);

}  // namespace spectralize
