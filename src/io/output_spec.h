#pragma once
// The spec of an image derived from a source image: same size, data window and display window,
// the first channels R, G, B (and A), HALF or FLOAT samples.

#include <OpenImageIO/imageio.h>

namespace spectralize {

/// A spec of `nchannels` channels over `source`'s windows, named R, G, B, then A if `alpha`;
/// the caller names any further channels. Cost: O(nchannels).
inline OIIO::ImageSpec output_spec_like(const OIIO::ImageSpec& source, int nchannels, bool half,
                                        bool alpha) {
  OIIO::ImageSpec spec(source.width, source.height, nchannels,
                       half ? OIIO::TypeDesc::HALF : OIIO::TypeDesc::FLOAT);
  spec.x = source.x;
  spec.y = source.y;
  spec.full_x = source.full_x;
  spec.full_y = source.full_y;
  spec.full_width = source.full_width;
  spec.full_height = source.full_height;
  spec.channelnames = {"R", "G", "B"};
  if (alpha) {
    spec.channelnames.push_back("A");
    spec.alpha_channel = 3;
  }
  return spec;
}

}  // namespace spectralize
