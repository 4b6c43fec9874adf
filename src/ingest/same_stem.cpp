#include "ingest/same_stem.h"
#include "text/strings.h"

#include <OpenImageIO/imageio.h>

#include <filesystem>

namespace fs = std::filesystem;

namespace spectralize {

std::string maketx_source(const std::string& file, const std::vector<std::string>& candidates) {
  std::string command;
  try {
    auto in = OIIO::ImageInput::open(file);
    if (!in) {
      (void)OIIO::geterror();
      return "";
    }
    for (const char* name : {"Software", "ImageDescription"}) {
      const std::string text = in->spec().get_string_attribute(name);
      const std::size_t at = text.find("maketx ");
      if (at != std::string::npos) {
        command.assign(1, ' ');
        command.append(text, at + 7);
        command.push_back(' ');
        break;
      }
    }
    in->close();
  } catch (const std::exception&) {
    return "";
  }
  if (command.empty()) return "";
  const std::string self = fs::path(file).filename().string();
  for (const std::string& c : candidates) {
    const std::string name = fs::path(c).filename().string();
    if (c == file || name == self) continue;
    // The argument as typed: "a.tif", "tex/a.tif" or "/lib/tex/a.tif", between spaces.
    for (std::size_t at = command.find(name); at != std::string::npos;
         at = command.find(name, at + 1)) {
      const char before = command[at - 1], after = command[at + name.size()];
      if ((before == ' ' || before == '/') && after == ' ') return c;
    }
  }
  return "";
}

std::vector<SameStemDecision> decide_same_stem(const std::vector<std::string>& inputs,
                                               const std::string& relative) {
  const std::size_t n = inputs.size();
  std::vector<SameStemDecision> out(n);
  std::vector<int> source(n, -1);
  for (std::size_t i = 0; i < n; ++i) {
    const std::string s = maketx_source(inputs[i], inputs);
    for (std::size_t j = 0; j < n; ++j)
      if (!s.empty() && inputs[j] == s) source[i] = static_cast<int>(j);
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
    out[i].note = "made by maketx from '" + clip(inputs[source[i]], 200) +
                  "' (its header's command line): one asset, converted from '" +
                  clip(inputs[r], 200) + "'";
  }
  return out;
}

}  // namespace spectralize
