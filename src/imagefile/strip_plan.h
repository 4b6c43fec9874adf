#pragma once
// How many rows a streamed job converts and writes at a time (docs/DESIGN.md §10): whole
// compression blocks (or tiles) of the output, enough of them per write for OpenEXR to compress
// in parallel on every worker, within a memory budget. Input tiles do not shape strips: the
// reader keeps the current row of tiles (input channels only), so a tiled input streams in the
// same output memory as a scanline one.

#include <cstddef>

namespace spectralize {

/// Rows per strip for an image of `height` rows whose output blocks (or tiles) have `block`
/// rows, `row_bytes` bytes of output samples per row, and `workers` compression threads: a
/// multiple of `block` (or the whole image); two blocks per worker within ~64 MB per strip
/// buffer, at least one per worker within 192 MB; at least 1, at most `height`. Cost: O(1).
int strip_rows(int height, int block, std::size_t row_bytes, int workers);

}  // namespace spectralize
