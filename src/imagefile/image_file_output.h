#pragma once
// A whole in-memory image (plots, figures) written to any format OpenImageIO writes, through
// imagefile/safe_output.h: checked to the last byte and renamed into place when complete.

#include <OpenImageIO/imagebuf.h>

#include <span>
#include <string>

namespace spectralize {

/// Writes `image` to `path` in the format of its extension with samples of `type`, never over
/// one of `inputs`, after checking that the format holds them (imagefile/output_formats.h). Throws
/// Error naming the file and the reason. Cost: encoding the image.
void write_image_file(const OIIO::ImageBuf& image, const std::string& path, OIIO::TypeDesc type,
                      std::span<const std::string> inputs = {});

/// True for the formats whose OIIO 2.4 writers write correctly through an IOProxy (OpenEXR,
/// PNG, JPEG, Radiance HDR: the output table's fact); others (TIFF leaves an unreadable file)
/// are written by name. Cost: O(formats).
bool writes_through_proxy(const std::string& format);

/// The first DejaVu Sans of the usual font folders (Debian's fonts-dejavu-core first), or "".
/// Cost: a few stat calls.
std::string find_font();

}  // namespace spectralize
