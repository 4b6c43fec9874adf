#include "imagefile/image_file_output.h"

#include <OpenImageIO/imageio.h>

#include <filesystem>
#include <vector>

#include "imagefile/output_formats.h"
#include "imagefile/safe_output.h"
#include "spectralize/core/error.h"

namespace spectralize {

void write_image_file(const OIIO::ImageBuf& image, const std::string& path, OIIO::TypeDesc type,
                      std::span<const std::string> inputs) {
  // What the format holds, before anything is written (docs/DESIGN.md §9).
  OIIO::ImageSpec spec = image.spec();
  OutputRequest want;
  want.samples = sample_type_name(type);
  want.channels = spec.nchannels;
  want.alpha = spec.alpha_channel >= 0;
  const OutputFormat& f = check_output(path, want, "");
  auto writer = OIIO::ImageOutput::create(path);
  if (!writer) {
    (void)OIIO::geterror();
    throw Error(quote(path, 200) + ": OpenImageIO cannot write this file type");
  }
  AtomicOutput file(path, WriteRules::named("the image"), inputs);
  spec.set_format(type);
  apply_compression(spec, f, "");
  // Through the checked proxy for the formats whose writers are known to use it correctly
  // (OIIO 2.4's TIFF writer through a proxy leaves an unreadable file), else by the
  // temporary's name; either way the file is read back before it is moved into place.
  const std::string format = writer->format_name();
  const bool proxied = f.proxy && writer->set_ioproxy(file.proxy());
  if (!writer->open(proxied ? path : file.path(), spec) || !image.write(writer.get()) ||
      !writer->close()) {
    const int err = errno;
    file.fail(quote(path, 200) + ": cannot write: " + writer->geterror() + image.geterror(), err);
  }
  // Read the whole file back: a writer can report success and still leave an unreadable file.
  file.check();
  auto back = OIIO::ImageInput::create(format);
  OIIO::ImageSpec back_spec;
  if (back && !back->open(file.path(), back_spec)) back.reset();
  std::vector<float> pixels;
  if (back)
    pixels.resize(static_cast<std::size_t>(back->spec().image_pixels()) * back->spec().nchannels);
  if (!back || back->spec().width != spec.width || back->spec().height != spec.height ||
      !back->read_image(0, 0, 0, back->spec().nchannels, OIIO::TypeFloat, pixels.data()))
    throw Error(quote(path, 200) + ": the written file does not read back: " +
                (back ? back->geterror() : OIIO::geterror()));
  back->close();
  file.commit();
}

bool writes_through_proxy(const std::string& format) {
  const OutputFormat* f = output_format_named(format);
  return f && f->proxy;
}

std::string find_font() {
  for (const char* f :
       {"/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf", "/usr/share/fonts/dejavu/DejaVuSans.ttf",
        "/usr/share/fonts/dejavu-sans-fonts/DejaVuSans.ttf", "/usr/share/fonts/TTF/DejaVuSans.ttf",
        "/usr/local/share/fonts/DejaVuSans.ttf"}) {
    std::error_code ec;
    if (std::filesystem::is_regular_file(f, ec)) return f;
  }
  return "";
}

}  // namespace spectralize
