#include "settings/map_kind.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <map>
#include <set>

#include "spectralize/core/error.h"
#include "text/strings.h"

namespace spectralize {

namespace {

using K = WordKind;
using P = WordPlace;

// The table (docs/DESIGN.md §9). Sources: Unreal's texture suffixes (T_<Name>_<Suffix>),
// Unity HDRP/URP map names, Substance 3D Painter's export presets, Quixel Megascans, USD
// Preview Surface, MaterialX standard_surface (Houdini/Karma), Arnold aiStandardSurface, and
// the abbreviations texture libraries use. Words that are everyday words too count only last.
// clang-format off
const NameWord kWords[] = {
    // Normals, bumps, heights, displacement.
    {"normal", K::data, P::anywhere, "normal map", ""},
    {"nrm", K::data, P::anywhere, "normal map", ""},
    {"nrml", K::data, P::anywhere, "normal map", ""},
    {"nml", K::data, P::anywhere, "normal map", ""},
    {"nor", K::data, P::last, "normal map", ""},
    {"norm", K::data, P::last, "normal map", ""},
    {"nm", K::data, P::last, "normal map", ""},
    {"n", K::data, P::engine, "normal map", ""},
    {"tangent", K::data, P::anywhere, "tangent map", ""},
    {"bump", K::data, P::anywhere, "bump map", ""},
    {"b", K::data, P::engine, "bump map", ""},
    {"height", K::data, P::anywhere, "height map", ""},
    {"hgt", K::data, P::anywhere, "height map", ""},
    {"h", K::data, P::engine, "height map", ""},
    {"parallax", K::data, P::anywhere, "parallax (height) map", ""},
    {"displacement", K::data, P::anywhere, "displacement map", ""},
    {"displace", K::data, P::anywhere, "displacement map", ""},
    {"disp", K::data, P::anywhere, "displacement map", ""},
    {"dp", K::data, P::last, "displacement map", ""},
    // Roughness, gloss, metal.
    {"roughness", K::data, P::anywhere, "roughness", ""},
    {"rgh", K::data, P::anywhere, "roughness", ""},
    {"rough", K::data, P::last, "roughness", ""},
    {"r", K::data, P::engine, "roughness", ""},
    {"glossiness", K::data, P::anywhere, "glossiness", ""},
    {"gloss", K::data, P::last, "glossiness", ""},
    {"smoothness", K::data, P::anywhere, "smoothness", ""},
    {"metallic", K::data, P::anywhere, "metallic", ""},
    {"metalness", K::data, P::anywhere, "metalness", ""},
    {"metal", K::data, P::last, "metalness", ""},
    {"mtl", K::data, P::last, "metalness", ""},
    {"mt", K::data, P::last, "metallic", ""},
    {"m", K::data, P::engine, "metallic or mask (data either way)", ""},
    // Packed maps.
    {"orm", K::data, P::anywhere, "packed occlusion, roughness, metallic", ""},
    {"arm", K::data, P::acronym, "packed occlusion, roughness, metallic",
     "the packed ARM map or the word arm"},
    {"arme", K::data, P::anywhere, "packed occlusion, roughness, metallic, emissive mask", ""},
    {"rma", K::data, P::anywhere, "packed roughness, metallic, occlusion", ""},
    {"mra", K::data, P::anywhere, "packed metallic, roughness, occlusion", ""},
    {"rmse", K::data, P::anywhere, "packed roughness, metallic, specular, emissive mask", ""},
    {"mr", K::data, P::last, "packed metallic, roughness", ""},
    {"maskmap", K::data, P::anywhere, "Unity's packed mask map", ""},
    {"detailmap", K::data, P::anywhere, "Unity's packed detail map", ""},
    // Occlusion, cavity, masks, opacity, ids, other scalar and vector data.
    {"ao", K::data, P::anywhere, "ambient occlusion", ""},
    {"occlusion", K::data, P::anywhere, "ambient occlusion", ""},
    {"ambientocclusion", K::data, P::anywhere, "ambient occlusion", ""},
    {"occ", K::data, P::last, "ambient occlusion", ""},
    {"o", K::data, P::engine, "ambient occlusion", ""},
    {"cavity", K::data, P::anywhere, "cavity map", ""},
    {"curvature", K::data, P::anywhere, "curvature map", ""},
    {"thickness", K::data, P::anywhere, "thickness map", ""},
    {"mask", K::data, P::last, "mask", ""},
    {"opacity", K::data, P::anywhere, "opacity", ""},
    {"cutout", K::data, P::anywhere, "opacity (cutout)", ""},
    {"transparency", K::data, P::anywhere, "opacity (transparency)", ""},
    {"alpha", K::data, P::last, "opacity (alpha)", ""},
    {"id", K::data, P::last, "ID map", ""},
    {"matid", K::data, P::anywhere, "material ID map", ""},
    {"ior", K::data, P::anywhere, "index of refraction", ""},
    {"anisotropy", K::data, P::anywhere, "anisotropy", ""},
    {"clearcoat", K::data, P::anywhere, "clear-coat weight", ""},
    {"transmission", K::data, P::last, "transmission weight", ""},
    {"scattering", K::data, P::last, "subsurface scattering weight", ""},
    {"flowmap", K::data, P::anywhere, "flow map", ""},
    {"velocity", K::data, P::anywhere, "velocity", ""},
    {"position", K::data, P::last, "position", ""},
    {"depth", K::data, P::last, "depth", ""},
    {"zdepth", K::data, P::anywhere, "depth", ""},
    // Grey data or a colour, by the map's channels.
    {"specular", K::data_if_grey, P::anywhere, "specular",
     "a specular colour (RGB) or a specular level (grey)"},
    {"spec", K::data_if_grey, P::last, "specular",
     "a specular colour (RGB) or a specular level (grey)"},
    {"s", K::data_if_grey, P::engine, "specular or smoothness",
     "specular colour (RGB) or smoothness (grey)"},
    {"a", K::data_if_grey, P::engine, "albedo or alpha", "albedo (RGB) or alpha (grey)"},
    {"translucency", K::data_if_grey, P::anywhere, "translucency",
     "a translucency colour (RGB) or weight (grey)"},
    {"subsurface", K::data_if_grey, P::last, "subsurface",
     "a subsurface colour (RGB) or weight (grey)"},
    {"sss", K::data_if_grey, P::last, "subsurface", "a subsurface colour (RGB) or weight (grey)"},
    {"sheen", K::data_if_grey, P::last, "sheen", "a sheen colour (RGB) or weight (grey)"},
    {"coat", K::data_if_grey, P::last, "coat", "a coat colour (RGB) or weight (grey)"},
    {"fuzz", K::data_if_grey, P::last, "fuzz", "a fuzz colour (RGB) or mask (grey)"},
    // A surface's colour.
    {"basecolor", K::reflectance, P::anywhere, "base colour", ""},
    {"basecolour", K::reflectance, P::anywhere, "base colour", ""},
    {"basemap", K::reflectance, P::anywhere, "Unity's base map (base colour)", ""},
    {"albedo", K::reflectance, P::anywhere, "albedo", ""},
    {"alb", K::reflectance, P::anywhere, "albedo", ""},
    {"diffuse", K::reflectance, P::anywhere, "diffuse colour", ""},
    {"diff", K::reflectance, P::anywhere, "diffuse colour", ""},
    {"dif", K::reflectance, P::last, "diffuse colour", ""},
    {"color", K::reflectance, P::last, "colour", ""},
    {"colour", K::reflectance, P::last, "colour", ""},
    {"col", K::reflectance, P::last, "colour", ""},
    {"bc", K::reflectance, P::last, "base colour", ""},
    {"d", K::reflectance, P::engine, "diffuse colour", ""},
    {"c", K::reflectance, P::engine, "colour", ""},
    // A light's colour.
    {"emissive", K::emission, P::anywhere, "emissive map", ""},
    {"emission", K::emission, P::anywhere, "emission map", ""},
    {"emissioncolor", K::emission, P::anywhere, "emission colour", ""},
    {"emissioncolour", K::emission, P::anywhere, "emission colour", ""},
    {"emissivecolor", K::emission, P::anywhere, "emissive colour", ""},
    {"emissivecolour", K::emission, P::anywhere, "emissive colour", ""},
    {"emit", K::emission, P::anywhere, "emission map", ""},
    {"em", K::emission, P::last, "emissive map", ""},
    {"e", K::emission, P::engine, "emissive map", ""},
    {"glow", K::emission, P::anywhere, "glow (emission) map", ""},
    {"illum", K::emission, P::anywhere, "self-illumination map", ""},
    {"selfillum", K::emission, P::anywhere, "self-illumination map", ""},
    {"incandescence", K::emission, P::anywhere, "incandescence (emission) map", ""},
    {"lightmap", K::emission, P::anywhere, "baked light", ""},
    {"hdri", K::emission, P::anywhere, "HDR environment", ""},
    {"hdr", K::emission, P::last, "HDR environment", ""},
    {"ibl", K::emission, P::anywhere, "image-based light", ""},
    {"env", K::emission, P::anywhere, "environment map", ""},
    {"envmap", K::emission, P::anywhere, "environment map", ""},
    {"environment", K::emission, P::anywhere, "environment map", ""},
    {"latlong", K::emission, P::anywhere, "lat-long environment", ""},
    {"equirect", K::emission, P::anywhere, "lat-long environment", ""},
    {"equirectangular", K::emission, P::anywhere, "lat-long environment", ""},
    {"panorama", K::emission, P::anywhere, "panorama", ""},
    {"pano", K::emission, P::last, "panorama", ""},
    {"skydome", K::emission, P::anywhere, "sky dome", ""},
    {"skybox", K::emission, P::anywhere, "sky box", ""},
    {"sky", K::emission, P::last, "sky", ""},
    {"sun", K::emission, P::last, "sun", ""},
    {"light", K::emission, P::folder, "lights",
     "a light source or a light tone (a light only as a folder, lights/)"},
};
// clang-format on

// Words after the map's kind that do not change it: resolutions, versions, UDIM tiles, levels,
// normal-map conventions, colour-space tags, bake levels, "map"/"tex".
const std::set<std::string>& decorations() {
  static const std::set<std::string> words = {
      "map",  "maps",    "tex", "texture", "textures", "img", "image", "opengl", "ogl",
      "gl",   "directx", "dx",  "srgb",    "linear",   "lin", "raw",   "acescg", "acescct",
      "aces", "rec709",  "hi",  "lo",      "high",     "low", "final", "bake",   "baked",
      "copy", "old",     "new", "udim",    "preview",  "lod", "ver",   "v"};
  return words;
}

bool all_digits(const std::string& s) {
  return !s.empty() &&
         std::all_of(s.begin(), s.end(), [](unsigned char c) { return std::isdigit(c); });
}

// 4k, 2K, 16bit, 512px: a resolution or a depth.
bool size_word(const std::string& s) {
  std::size_t i = 0;
  while (i < s.size() && std::isdigit(static_cast<unsigned char>(s[i]))) ++i;
  if (i == 0 || i == s.size()) return false;
  const std::string rest = s.substr(i);
  return rest == "k" || rest == "bit" || rest == "bits" || rest == "px" || rest == "p";
}

bool decoration(const std::vector<NameToken>& t, std::size_t i) {
  const std::string& s = t[i].text;
  if (all_digits(s) || size_word(s)) return true;
  // "v" and "lod" only before a number (v002, LOD0); "map" and the others anywhere.
  if (s == "v" || s == "lod" || s == "ver") return i + 1 < t.size() && all_digits(t[i + 1].text);
  return decorations().count(s) > 0;
}

// The index of the last word that is not a decoration, or -1.
int last_word(const std::vector<NameToken>& t) {
  for (int i = static_cast<int>(t.size()) - 1; i >= 0; --i)
    if (!decoration(t, static_cast<std::size_t>(i))) return i;
  return -1;
}

// Unreal's texture prefix: T_Rock_N, TX_Rock_N, Tex_Rock_N.
bool engine_style(const std::vector<NameToken>& t, int last) {
  if (t.empty() || last < 2) return false;
  const std::string& p = t[0].text;
  return p == "t" || p == "tx" || p == "tex";
}

struct Hit {
  const NameWord* word = nullptr;
  int start = -1, end = -1;
  std::string text;  // as matched (a folder's plural: "lights")
};

using Table = std::map<std::string, const NameWord*>;

// The deciding word of one name (a stem, or a folder when `folder`): the counting word that
// ends last, the longer where two end together. `skipped` gets ambiguous last words that did
// not count there.
Hit decide(const std::vector<NameToken>& t, const Table& table, bool folder,
           std::vector<const NameWord*>* skipped) {
  const int last = last_word(t);
  const bool engine = engine_style(t, last);
  Hit best;
  auto consider = [&](const std::string& text, int start, int end) {
    auto it = table.find(text);
    std::string shown = text;
    // Folders are often plural: normals/, masks/, lights/, hdris/.
    if (it == table.end() && folder && text.size() > 2 && text.back() == 's') {
      it = table.find(text.substr(0, text.size() - 1));
    }
    if (it == table.end()) return;
    const NameWord* w = it->second;
    const bool single = start == end;
    bool counts = false;
    switch (w->place) {
      case P::anywhere:
        counts = true;
        break;
      case P::last:
        counts = end == last;
        break;
      case P::engine:
        counts = !folder && single && end == last && engine;
        break;
      case P::acronym:
        counts = !folder && single && end == last && (engine || t[end].capitals);
        break;
      case P::folder:
        counts = folder && end == last;
        break;
    }
    if (!counts) {
      // A letter outside an engine-style name is only a letter (plan_a, eye_r).
      if (skipped && end == last && !w->ambiguity.empty() && w->place != P::engine)
        skipped->push_back(w);
      return;
    }
    if (!best.word || end > best.end ||
        (end == best.end && w->word.size() > best.word->word.size()))
      best = {w, start, end, shown};
  };
  for (int i = 0; i < static_cast<int>(t.size()); ++i) {
    consider(t[i].text, i, i);
    if (i + 1 < static_cast<int>(t.size())) consider(t[i].text + t[i + 1].text, i, i + 1);
  }
  return best;
}

MapKind kind_of(WordKind k) {
  switch (k) {
    case K::data:
      return MapKind::data;
    case K::reflectance:
      return MapKind::reflectance;
    case K::emission:
      return MapKind::emission;
    case K::data_if_grey:
      return MapKind::none;
  }
  return MapKind::none;
}

std::string place_note(const NameWord& w, bool folder) {
  if (folder) return "";
  switch (w.place) {
    case P::engine:
      return " (engine-style suffix)";
    case P::acronym:
      return " (packed-map suffix)";
    case P::last:
      return " (last word)";
    default:
      return "";
  }
}

// Items of an edit: (sign, word, kind) with sign '+', '-' or 0.
struct EditItem {
  char sign = 0;
  std::string word;
  WordKind kind = WordKind::data;
};

std::vector<EditItem> parse_edit(std::string_view text, bool colour) {
  std::vector<EditItem> items;
  std::string lower(text);
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  std::size_t from = 0;
  int signed_items = 0;
  while (from <= lower.size()) {
    const std::size_t comma = lower.find(',', from);
    std::string item =
        lower.substr(from, comma == std::string::npos ? std::string::npos : comma - from);
    from = comma == std::string::npos ? lower.size() + 1 : comma + 1;
    const std::string given = item;
    EditItem e;
    e.kind = colour ? WordKind::reflectance : WordKind::data;
    if (!item.empty() && (item[0] == '+' || item[0] == '-')) {
      e.sign = item[0];
      item = item.substr(1);
      ++signed_items;
    }
    if (colour) {
      const std::size_t colon = item.find(':');
      if (colon != std::string::npos) {
        const std::string k = item.substr(colon + 1);
        if (k == "emission")
          e.kind = WordKind::emission;
        else if (k != "reflectance")
          throw Error("'" + clip(given) + "': a colour word's kind is :emission or :reflectance");
        if (e.sign == '-') throw Error("'" + clip(given) + "': a removed word takes no kind");
        item = item.substr(0, colon);
      }
    }
    if (item.empty() ||
        item.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789") != std::string::npos)
      throw Error("'" + clip(given) +
                  "' is not a word (letters and digits; the list is comma-separated)");
    e.word = item;
    items.push_back(e);
  }
  if (signed_items != 0 && signed_items != static_cast<int>(items.size()))
    throw Error(
        "mixes signed and plain words: a plain list replaces the table's words, a list of "
        "+word and -word edits them");
  for (const EditItem& e : items) {
    if (e.sign != '-') continue;
    bool found = false;
    for (const NameWord& w : kWords)
      found =
          found || (w.word == e.word && (colour ? w.kind == K::reflectance || w.kind == K::emission
                                                : w.kind == K::data || w.kind == K::data_if_grey));
    if (!found)
      throw Error(
          "-" + e.word + ": not a " + (colour ? "colour" : "data") +
          " word of the table (see 'In a studio pipeline' in the guide, docs/guide/pipeline.md)");
  }
  return items;
}

std::string canonical(const std::vector<EditItem>& items, bool colour) {
  std::string out;
  for (const EditItem& e : items) {
    if (!out.empty()) out += ",";
    if (e.sign) out += e.sign;
    out += e.word;
    if (colour && e.kind == WordKind::emission) out += ":emission";
  }
  return out;
}

bool is_colour(WordKind k) {
  return k == K::reflectance || k == K::emission;
}

void apply_edit(std::vector<NameWord>& words, const std::vector<EditItem>& items, bool colour) {
  if (items.empty()) return;
  auto of_this_list = [&](const NameWord& w) {
    return colour ? is_colour(w.kind) : !is_colour(w.kind);
  };
  auto erase_word = [&](const std::string& word) {
    words.erase(std::remove_if(words.begin(), words.end(),
                               [&](const NameWord& w) { return w.word == word; }),
                words.end());
  };
  if (items[0].sign == 0)
    words.erase(std::remove_if(words.begin(), words.end(), of_this_list), words.end());
  for (const EditItem& e : items) {
    if (e.sign == '-') {
      words.erase(
          std::remove_if(words.begin(), words.end(),
                         [&](const NameWord& w) { return w.word == e.word && of_this_list(w); }),
          words.end());
      continue;
    }
    erase_word(e.word);  // a word has one meaning: the user's
    NameWord w;
    w.word = e.word;
    w.kind = e.kind;
    // A letter the user names counts as any name's last word (rock_n): the user's convention.
    w.place = e.word.size() == 1 ? P::last : P::anywhere;
    w.meaning = std::string(colour ? "--colour-names" : "--data-names") + " word";
    words.push_back(w);
  }
}

}  // namespace

std::span<const NameWord> builtin_name_words() {
  return kWords;
}

std::string check_name_edit(std::string_view text, bool colour) {
  return canonical(parse_edit(text, colour), colour);
}

std::vector<NameWord> name_words_in_force(const std::string& data_edit,
                                          const std::string& colour_edit) {
  std::vector<NameWord> words(std::begin(kWords), std::end(kWords));
  if (!data_edit.empty()) apply_edit(words, parse_edit(data_edit, false), false);
  if (!colour_edit.empty()) apply_edit(words, parse_edit(colour_edit, true), true);
  return words;
}

std::vector<NameToken> name_tokens(std::string_view name) {
  std::vector<NameToken> out;
  std::string cur;
  bool all_caps = true;
  auto flush = [&] {
    if (cur.empty()) return;
    NameToken t;
    t.capitals =
        all_caps && cur.size() > 1 &&
        std::any_of(cur.begin(), cur.end(), [](unsigned char c) { return std::isalpha(c); });
    for (char& c : cur) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    t.text = cur;
    out.push_back(std::move(t));
    cur.clear();
    all_caps = true;
  };
  for (std::size_t i = 0; i < name.size(); ++i) {
    const unsigned char c = static_cast<unsigned char>(name[i]);
    if (!std::isalnum(c)) {
      flush();
      continue;
    }
    if (!cur.empty()) {
      const unsigned char prev = static_cast<unsigned char>(name[i - 1]);
      const bool next_lower =
          i + 1 < name.size() && std::islower(static_cast<unsigned char>(name[i + 1]));
      if ((std::isupper(c) && std::islower(prev)) ||                // baseColor
          (std::isupper(c) && std::isupper(prev) && next_lower) ||  // ORMMap: ORM|Map
          (std::isdigit(c) && std::isalpha(prev)))                  // Rock01: Rock|01
        flush();
    }
    if (std::islower(c)) all_caps = false;
    cur += static_cast<char>(c);
  }
  flush();
  return out;
}

NameVerdict map_kind_by_name(const std::string& path, const std::vector<NameWord>& words) {
  Table table;
  for (const NameWord& w : words) table[w.word] = &w;
  NameVerdict v;
  const std::filesystem::path p = std::filesystem::path(path).lexically_normal();
  const std::string stem = p.stem().string();
  std::vector<const NameWord*> skipped;
  Hit hit = decide(name_tokens(stem), table, false, &skipped);
  std::string where = "name word '";
  std::string of = "' of '" + clip(stem) + "'";
  bool folder = false;
  if (!hit.word) {
    for (const NameWord* w : skipped)
      v.warnings.push_back("its name's last word '" + w->word + "' can mean " + w->ambiguity +
                           ": it does not decide what the map holds (--data-names +" + w->word +
                           " or --colour-names +" + w->word + "[:emission] to make it)");
    // The parent folder, then the grandparent.
    std::filesystem::path dir = p.parent_path();
    for (int level = 0; level < 2 && !dir.empty(); ++level, dir = dir.parent_path()) {
      const std::string name = dir.filename().string();
      if (name.empty() || name == "." || name == ".." || name == "/") break;
      hit = decide(name_tokens(name), table, true, nullptr);
      if (hit.word) {
        where = "folder word '";
        of = "' of '" + clip(name) + "/'";
        folder = true;
        break;
      }
    }
  }
  if (!hit.word) return v;
  v.word = hit.word->word;
  v.reason = where + hit.text + of + place_note(*hit.word, folder) + ": " + hit.word->meaning;
  v.kind = kind_of(hit.word->kind);
  if (hit.word->kind == K::data_if_grey) {
    v.needs_channels = true;
    v.ambiguity = hit.word->ambiguity;
  }
  return v;
}

void resolve_by_channels(NameVerdict& v, bool grey) {
  if (!v.needs_channels) return;
  v.needs_channels = false;
  v.kind = grey ? MapKind::data : MapKind::reflectance;
  const std::string taken = grey ? "a grey map: data" : "a colour map: a surface's colour";
  v.reason += "; " + taken;
  if (!v.ambiguity.empty())
    v.warnings.push_back("'" + v.word + "' can mean " + v.ambiguity + "; " + taken);
}

std::string_view to_string(MapKind kind) {
  switch (kind) {
    case MapKind::data:
      return "data";
    case MapKind::reflectance:
      return "reflectance";
    case MapKind::emission:
      return "emission";
    case MapKind::none:
      return "none";
  }
  return "none";
}

}  // namespace spectralize
