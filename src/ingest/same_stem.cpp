#include "ingest/same_stem.h"
#include "text/strings.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

#include <filesystem>

namespace fs = std::filesystem;

namespace spectralize {

namespace {

// A header's facts for telling a texture from its source.
struct Header {
  bool read = false;
  int width = 0, height = 0, channels = 0;
  bool texture = false;  // made by maketx (or txmake): it says its texture format
  std::string command;   // the maketx command line it records, " a.tif -o a.tx ", or ""
};

Header header_of(const std::string& file) {
  Header h;
  try {
    auto in = OIIO::ImageInput::open(file);
    if (!in) {
      (void)OIIO::geterror();
      return h;
    }
    const OIIO::ImageSpec& spec = in->spec();
    h.read = true;
    h.width = spec.width;
    h.height = spec.height;
    h.channels = spec.nchannels;
    h.texture = !spec.get_string_attribute("textureformat").empty();
    for (const char* name : {"Software", "ImageDescription"}) {
      const std::string text = spec.get_string_attribute(name);
      const std::size_t at = text.find("maketx ");
      if (at != std::string::npos) {
        h.command.assign(1, ' ');
        h.command.append(text, at + 7);
        h.command.push_back(' ');
        break;
      }
    }
    in->close();
  } catch (const std::exception&) {
    return Header{};
  }
  return h;
}

// True when the first level of `a` and the image `b` hold the same pixels, within an 8-bit step.
// Read through OIIO's image cache: memory stays bounded whatever their size.
bool same_pixels(const std::string& a, const std::string& b) {
  OIIO::ImageBuf first(a), second(b);
  const auto result = OIIO::ImageBufAlgo::compare(first, second, 1.0f / 255, 1.0f / 255);
  (void)first.geterror();
  (void)second.geterror();
  (void)OIIO::geterror();
  return !result.error && result.nfail == 0 && result.nwarn == 0;
}

}  // namespace

TextureSource texture_source(const std::string& file, const std::vector<std::string>& candidates) {
  const Header h = header_of(file);
  if (!h.read) return {};
  const std::string self = fs::path(file).filename().string();
  if (!h.command.empty()) {
    for (const std::string& c : candidates) {
      const std::string name = fs::path(c).filename().string();
      if (c == file || name == self) continue;
      // The argument as typed: "a.tif", "tex/a.tif" or "/lib/tex/a.tif", between spaces.
      for (std::size_t at = h.command.find(name); at != std::string::npos;
           at = h.command.find(name, at + 1)) {
        const char before = h.command[at - 1], after = h.command[at + name.size()];
        if ((before == ' ' || before == '/') && after == ' ')
          return {c, "its header's command line"};
      }
    }
    return {};
  }
  // OIIO 3's maketx records no command line unless asked (--history): a texture is taken as
  // made from the one image of its name that is no texture and whose pixels its first level
  // holds (within an 8-bit step: maketx may change the sample type).
  if (!h.texture) return {};
  std::string found;
  for (const std::string& c : candidates) {
    if (c == file || fs::path(c).filename().string() == self) continue;
    const Header other = header_of(c);
    if (!other.read || other.texture || other.width != h.width || other.height != h.height ||
        other.channels != h.channels || !same_pixels(file, c))
      continue;
    if (!found.empty()) return {};  // two could be its source: neither is assumed
    found = c;
  }
  if (found.empty()) return {};
  return {found,
          "a texture whose header records no command line, holding the pixels of the one other "
          "image of its name that has them"};
}

std::vector<SameStemDecision> decide_same_stem(const std::vector<std::string>& inputs,
                                               const std::string& relative) {
  const std::size_t n = inputs.size();
  std::vector<SameStemDecision> out(n);
  std::vector<int> source(n, -1);
  std::vector<std::string> how(n);
  for (std::size_t i = 0; i < n; ++i) {
    const TextureSource t = texture_source(inputs[i], inputs);
    for (std::size_t j = 0; j < n; ++j)
      if (!t.source.empty() && inputs[j] == t.source) source[i] = static_cast<int>(j);
    how[i] = t.how;
  }
  // The root of each input (a .tx of a .tx of a .tif: the .tif), ignoring cycles.
  auto root = [&](std::size_t i) {
    std::size_t r = i;
    for (std::size_t steps = 0; source[r] >= 0 && steps < n; ++steps)
      r = static_cast<std::size_t>(source[r]);
    return source[r] >= 0 ? i : r;
  };
  std::vector<std::size_t> roots;
  for (std::size_t i = 0; i < n; ++i)
    if (root(i) == i) roots.push_back(i);
  const std::string base = relative.size() > 4 ? relative.substr(0, relative.size() - 4) : relative;
  auto own_name = [&](std::size_t i) {
    return roots.size() > 1 ? base + fs::path(inputs[i]).extension().string() + ".exr" : relative;
  };
  for (std::size_t i : roots) {
    out[i].relative = own_name(i);
    if (roots.size() > 1) {
      std::string others;
      for (std::size_t j : roots)
        if (j != i) others += (others.empty() ? "'" : ", '") + clip(inputs[j], 200) + "'";
      out[i].note = "another image of the same name (" + others + ") is not derived from it: " +
                    "each keeps its own output, named with its extension";
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t r = root(i);
    if (r == i) continue;
    out[i].relative = out[r].relative;
    out[i].derived_from = inputs[r];
    out[i].note = "made by maketx from '" + clip(inputs[source[i]], 200) + "' (" + how[i] +
                  "): one asset, converted from '" + clip(inputs[r], 200) + "'";
  }
  return out;
}

}  // namespace spectralize
