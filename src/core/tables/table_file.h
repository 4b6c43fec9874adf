#pragma once
// The render-time table file (.spztab, docs/DESIGN.md §14; the layout is
// include/spectralize/rt_format.h): an ExactTable built whole, with its colour space, settings
// and the gamut planes of the mapping, as bytes that <spectralize/rt.h> reads without this
// library, OIIO or OCIO.

#include <string>

#include "core/tables/exact_table.h"
#include "spectralize/core/spectralizer.h"

namespace spectralize {

/// What a table file says about where its RGB comes from.
struct TableFileInfo {
  std::string colorspace;  // the OCIO colour space's name (<= 127 bytes)
  std::string interop_id;  // its colour interop ID, or ""
};

/// The bytes of a table file for `table` (built: ExactTable::build) of `spectralizer`'s
/// settings. Throws Error when a name does not fit the header. Cost: O(file size), a few MB.
std::string encode_table_file(const ExactTable& table, const Spectralizer& spectralizer,
                              const TableFileInfo& info);

}  // namespace spectralize
