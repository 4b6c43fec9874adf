#include "imagefile/exr_scanline_writer.h"

#include <Iex.h>
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfIO.h>
#include <ImfOutputFile.h>
#include <ImfStdIO.h>

#include <algorithm>
#include <cctype>
#include <cstring>
#include <vector>

#include "imagefile/openexr_compat.h"
#include "spectralize/core/error.h"

namespace spectralize {

namespace {

constexpr int kDefaultZipLevel = 4;
constexpr float kDefaultDwaLevel = 45.0f;

// "zip:4" -> ("zip", 4); no level: -1.
std::pair<std::string, int> split_compression(const std::string& text) {
  const auto colon = text.find(':');
  std::string name = text.substr(0, colon);
  for (char& c : name) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  int level = -1;
  if (colon != std::string::npos) {
    try {
      level = std::stoi(text.substr(colon + 1));
    } catch (const std::exception&) {
      level = -1;
    }
  }
  return {name, level};
}

// OpenEXR's output stream over an OIIO IOProxy (the checked temporary file): a short write is
// an exception, which OpenEXR passes on, and is remembered: OpenEXR's OutputFile writes the
// line offset table in its destructor, which swallows the exception.
class ProxyStream final : public Imf::OStream {
 public:
  ProxyStream(OIIO::Filesystem::IOProxy* proxy, const std::string& file)
      : Imf::OStream(file.c_str()), proxy_(proxy) {}
  void write(const char c[], int n) override {
    if (proxy_->write(c, static_cast<std::size_t>(n)) != static_cast<std::size_t>(n))
      fail("write failed");
  }
  uint64_t tellp() override { return static_cast<uint64_t>(proxy_->tell()); }
  void seekp(uint64_t pos) override {
    if (!proxy_->seek(static_cast<int64_t>(pos))) fail("seek failed");
  }
  /// The first failure ("" : none). Cost: O(1).
  const std::string& failure() const { return failure_; }

 private:
  [[noreturn]] void fail(const char* what) {
    if (failure_.empty()) failure_ = what;
    throw Iex::IoExc(what);
  }

  OIIO::Filesystem::IOProxy* proxy_;
  std::string failure_;
};

// The header OpenImageIO writes for `spec`: a one-row file of the spec made in memory by OIIO,
// its header read back by OpenEXR (the attributes only, not a whole file's reader), with the
// real data window.
Imf::Header oiio_header(const OIIO::ImageSpec& spec, const std::string& file) {
  OIIO::ImageSpec one = spec;
  one.height = 1;
  std::vector<unsigned char> bytes;
  {
    OIIO::Filesystem::IOVecOutput memory(bytes);
    auto out = OIIO::ImageOutput::create("openexr");
    if (!out || !out->set_ioproxy(&memory) || !out->open(file, one))
      throw Error("'" + file + "': cannot make the OpenEXR header: " +
                  (out ? out->geterror() : OIIO::geterror()));
    std::vector<char> row(one.scanline_bytes(true), 0);
    if (!out->write_scanline(one.y, 0, OIIO::TypeUnknown, row.data()) || !out->close())
      throw Error("'" + file + "': cannot make the OpenEXR header: " + out->geterror());
  }
  // The header alone (magic and version, then the attributes): not a whole file's reader.
  if (bytes.size() < 8) throw Error("'" + file + "': cannot make the OpenEXR header: too short");
  int version = 0;
  std::memcpy(&version, bytes.data() + 4, 4);  // little-endian, as OpenEXR stores it
  Imf::StdISStream in;
  in.str(std::string(bytes.begin() + 8, bytes.end()));
  Imf::Header h;
  try {
    h.readFrom(in, version);
  } catch (const std::exception& e) {
    throw Error("'" + file + "': cannot make the OpenEXR header: " + e.what());
  }
  h.dataWindow() = Imath::Box2i(Imath::V2i(spec.x, spec.y),
                                Imath::V2i(spec.x + spec.width - 1, spec.y + spec.height - 1));
  // OpenEXR keeps zip's and DWA's levels in memory only (the file does not record them): set
  // them again; plain "zip" is level 4 and plain DWA 45 (OpenEXR 3.1's defaults, stated so they
  // cannot drift with versions).
  const auto [name, level] = split_compression(spec.get_string_attribute("compression"));
  if (name == "zip" || name == "zips")
    h.zipCompressionLevel() = level >= 0 ? level : kDefaultZipLevel;
  if (name == "dwaa" || name == "dwab")
    h.dwaCompressionLevel() = level >= 0 ? static_cast<float>(level) : kDefaultDwaLevel;
  return h;
}

}  // namespace

int exr_block_rows(const std::string& compression) {
  const std::string name = split_compression(compression).first;
  for (const ExrCompression& c : exr_compressions())
    if (c.name == name) return c.block_rows;
  return 1;
}

struct ExrScanlineWriter::Impl {
  std::string file;
  ProxyStream stream;
  std::unique_ptr<Imf::OutputFile> out;
  int x = 0, width = 0, nchannels = 0;
  std::size_t pixel_bytes = 0;
  std::vector<std::string> names;
  std::vector<Imf::PixelType> types;
  std::vector<std::size_t> offsets;
  Impl(OIIO::Filesystem::IOProxy* proxy, const std::string& f) : file(f), stream(proxy, f) {}
};

ExrScanlineWriter::ExrScanlineWriter(const OIIO::ImageSpec& spec, OIIO::Filesystem::IOProxy* proxy,
                                     const std::string& file, int workers)
    : impl_(std::make_unique<Impl>(proxy, file)) {
  Impl& m = *impl_;
  m.x = spec.x;
  m.width = spec.width;
  m.nchannels = spec.nchannels;
  m.pixel_bytes = spec.pixel_bytes(true);
  std::size_t offset = 0;
  for (int c = 0; c < spec.nchannels; ++c) {
    const OIIO::TypeDesc t = spec.channelformat(c);
    if (t != OIIO::TypeHalf && t != OIIO::TypeFloat)
      throw Error("'" + file + "': channel " + spec.channelnames[c] + " is " + t.c_str() +
                  "; spectral OpenEXR is half or float");
    m.names.push_back(spec.channelnames[c]);
    m.types.push_back(t == OIIO::TypeHalf ? Imf::HALF : Imf::FLOAT);
    m.offsets.push_back(offset);
    offset += t.size();
  }
  // One block (a small image) leaves nothing to compress in parallel: no worker line buffers,
  // each with its own compressor.
  const int rows = exr_block_rows(spec.get_string_attribute("compression", "zip"));
  if (spec.height <= rows) workers = 0;
  try {
    m.out = std::make_unique<Imf::OutputFile>(m.stream, oiio_header(spec, file), workers);
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    throw Error("'" + file + "': cannot write: " + e.what());
  }
}

ExrScanlineWriter::~ExrScanlineWriter() = default;

void ExrScanlineWriter::write(int y, int rows, const void* data) {
  Impl& m = *impl_;
  const std::size_t row_bytes = m.pixel_bytes * static_cast<std::size_t>(m.width);
  // OpenEXR addresses the frame buffer by absolute (x, y): the base is where (0, 0) would be.
  char* base = static_cast<char*>(const_cast<void*>(data)) -
               static_cast<std::ptrdiff_t>(m.x) * static_cast<std::ptrdiff_t>(m.pixel_bytes) -
               static_cast<std::ptrdiff_t>(y) * static_cast<std::ptrdiff_t>(row_bytes);
  try {
    Imf::FrameBuffer fb;
    for (int c = 0; c < m.nchannels; ++c)
      fb.insert(m.names[c], Imf::Slice(m.types[c], base + m.offsets[c], m.pixel_bytes, row_bytes));
    m.out->setFrameBuffer(fb);
    m.out->writePixels(rows);
  } catch (const std::exception& e) {
    throw Error("'" + m.file + "': write failed: " + e.what());
  }
}

void ExrScanlineWriter::close() {
  Impl& m = *impl_;
  const bool failed_before = !m.stream.failure().empty();
  try {
    m.out.reset();  // writes the line offset table
  } catch (const std::exception& e) {
    throw Error("'" + m.file + "': write failed: " + e.what());
  }
  // OutputFile's destructor throws nothing: a failure there is known to the stream only.
  if (!m.stream.failure().empty())
    throw Error("'" + m.file + "': write failed: " + m.stream.failure() +
                (failed_before ? " (the file is incomplete)" : " (the line offset table)"));
}

}  // namespace spectralize
