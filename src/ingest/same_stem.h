#pragma once
// Inputs that would write one output (docs/DESIGN.md §12): tex/a.png, tex/a.tif and tex/a.tx
// all name a.exr. A texture derived from another of them (a .tx whose header records the
// maketx command that made it from a.tif, or, where maketx records none, the one image of its
// name whose pixels it holds) is the same asset: its source is converted and the derived file says
// so. The others are distinct images: each keeps its own output, named with its extension
// (a.png.exr, a.tif.exr), never a failure and never an overwrite.

#include <string>
#include <vector>

namespace spectralize {

/// What becomes of one input of a group naming the same output.
struct SameStemDecision {
  std::string relative;      // its output, relative to the destination
  std::string derived_from;  // the input it was made from ("": converted itself)
  std::string note;          // why, for the manifest ("" when nothing changed)
};

/// Where a texture came from: the input it was made from, and how that is known.
struct TextureSource {
  std::string source;  // "": not known to be made from another input
  std::string how;     // "its header's command line", or the size-and-channels match
};

/// The input among `candidates` that `file` was made from by maketx: the one its header's
/// command line names by file name (OIIO's "Software" attribute, "OpenImageIO 2.4 : maketx
/// a.tif -o a.tx"), else, for a texture whose header records no command line (OIIO 3's maketx
/// without --history), the one candidate that is no texture and whose pixels its first level
/// holds. Never throws (an unreadable file names none). Cost: reading the headers, and for a
/// texture without a command line the pixels of it and of the candidates of its size.
TextureSource texture_source(const std::string& file, const std::vector<std::string>& candidates);

/// Decides a group of inputs whose outputs are all `relative` (ending in .exr): one decision
/// per input, in order. Derived inputs follow their source (to its root, if derived in turn);
/// when more than one input remains, each is renamed "<relative without .exr><its extension>
/// .exr". Cost: a header read per input.
std::vector<SameStemDecision> decide_same_stem(const std::vector<std::string>& inputs,
                                               const std::string& relative);

}  // namespace spectralize
