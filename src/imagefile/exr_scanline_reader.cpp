#include "imagefile/exr_scanline_reader.h"

#include <ImfChannelList.h>
#include <ImfCompression.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfPartType.h>

#include <algorithm>
#include <exception>

#include "spectralize/core/error.h"
#include "text/strings.h"

namespace spectralize {

namespace {

// Rows per chunk of each compression (OpenEXR's own numbers).
int chunk_rows_of(Imf::Compression c) {
  switch (c) {
    case Imf::ZIP_COMPRESSION:
    case Imf::PXR24_COMPRESSION:
      return 16;
    case Imf::PIZ_COMPRESSION:
    case Imf::B44_COMPRESSION:
    case Imf::B44A_COMPRESSION:
    case Imf::DWAA_COMPRESSION:
      return 32;
    case Imf::DWAB_COMPRESSION:
      return 256;
    default:
      return 1;  // none, rle, zips
  }
}

}  // namespace

struct ExrScanlineReader::Impl {
  std::string path;
  std::unique_ptr<Imf::InputFile> in;
  std::vector<std::string> names;
  int x = 0, y = 0, width = 0, chunk = 1, kept = 1;
};

ExrScanlineReader::ExrScanlineReader(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
ExrScanlineReader::~ExrScanlineReader() = default;

std::unique_ptr<ExrScanlineReader> ExrScanlineReader::open(const std::string& path,
                                                           const std::vector<std::string>& names,
                                                           std::size_t budget, int workers) {
  try {
    // The header first, without threads (no chunk buffers yet), to size the real reader.
    std::size_t chunk_bytes = 0;
    int chunk = 1;
    {
      Imf::InputFile probe(path.c_str(), 0);
      const Imf::Header& h = probe.header();
      if ((h.hasType() && h.type() != Imf::SCANLINEIMAGE) || h.hasTileDescription()) return nullptr;
      std::size_t pixel_bytes = 0;
      for (auto c = h.channels().begin(); c != h.channels().end(); ++c) {
        if (c.channel().xSampling != 1 || c.channel().ySampling != 1) return nullptr;
        pixel_bytes += c.channel().type == Imf::HALF ? 2 : 4;
      }
      for (const std::string& n : names) {
        const Imf::Channel* c = h.channels().findChannel(n);
        if (!c || c->type == Imf::UINT) return nullptr;  // OIIO normalises integers
      }
      const auto& dw = h.dataWindow();
      chunk = chunk_rows_of(h.compression());
      chunk_bytes = static_cast<std::size_t>(dw.max.x - dw.min.x + 1) * pixel_bytes *
                    static_cast<std::size_t>(chunk);
    }
    // OpenEXR keeps max(1, 2 x threads) chunks, each about twice its decoded size (the chunk
    // and its decompressor's buffers): as many threads as the budget holds.
    const std::size_t fits =
        std::max<std::size_t>(1, budget / std::max<std::size_t>(1, 2 * chunk_bytes));
    const int threads = std::clamp(static_cast<int>(fits / 2), 0, std::max(0, workers));
    auto m = std::make_unique<Impl>();
    m->path = path;
    m->in = std::make_unique<Imf::InputFile>(path.c_str(), threads);
    const auto& dw = m->in->header().dataWindow();
    m->x = dw.min.x;
    m->y = dw.min.y;
    m->width = dw.max.x - dw.min.x + 1;
    m->names = names;
    m->chunk = chunk;
    m->kept = std::max(1, 2 * threads);
    return std::unique_ptr<ExrScanlineReader>(new ExrScanlineReader(std::move(m)));
  } catch (const std::exception&) {
    return nullptr;  // OIIO reads it, and reports what is wrong
  }
}

int ExrScanlineReader::chunk_rows() const {
  return impl_->chunk;
}

int ExrScanlineReader::chunks_kept() const {
  return impl_->kept;
}

void ExrScanlineReader::read(int y0, int y1, float* out) {
  Impl& m = *impl_;
  const std::size_t nch = m.names.size();
  const std::size_t pixel = nch * sizeof(float), row = pixel * static_cast<std::size_t>(m.width);
  // OpenEXR addresses the frame buffer by absolute (x, y): the base is where (0, 0) would be.
  const int top = m.y + y0;
  char* base = reinterpret_cast<char*>(out) -
               static_cast<std::ptrdiff_t>(m.x) * static_cast<std::ptrdiff_t>(pixel) -
               static_cast<std::ptrdiff_t>(top) * static_cast<std::ptrdiff_t>(row);
  try {
    Imf::FrameBuffer fb;
    for (std::size_t c = 0; c < nch; ++c)
      fb.insert(m.names[c], Imf::Slice(Imf::FLOAT, base + c * sizeof(float), pixel, row));
    m.in->setFrameBuffer(fb);
    m.in->readPixels(top, m.y + y1 - 1);
  } catch (const std::exception& e) {
    throw Error("'" + clip(m.path, 200) + "': cannot read rows " + std::to_string(y0) + ".." +
                std::to_string(y1 - 1) + ": " + clip(e.what(), 300));
  }
}

}  // namespace spectralize
