#include "text/json_text.h"

#include <array>
#include <nlohmann/json.hpp>

#include "spectralize/core/error.h"

namespace spectralize {

namespace {

using Json = nlohmann::ordered_json;

// The length of the valid UTF-8 sequence that starts at `at`, or 0 (RFC 3629's table).
std::size_t sequence_length(std::string_view t, std::size_t at) {
  const auto b = [&](std::size_t i) { return static_cast<unsigned char>(t[at + i]); };
  const unsigned char c = b(0);
  if (c < 0x80) return 1;
  std::size_t n = 0;
  unsigned char lo = 0x80, hi = 0xBF;  // the allowed range of the second byte
  if (c >= 0xC2 && c <= 0xDF) {
    n = 2;
  } else if (c >= 0xE0 && c <= 0xEF) {
    n = 3;
    if (c == 0xE0) lo = 0xA0;  // no overlong forms
    if (c == 0xED) hi = 0x9F;  // no surrogates
  } else if (c >= 0xF0 && c <= 0xF4) {
    n = 4;
    if (c == 0xF0) lo = 0x90;
    if (c == 0xF4) hi = 0x8F;  // nothing above U+10FFFF
  } else {
    return 0;
  }
  if (at + n > t.size()) return 0;
  if (b(1) < lo || b(1) > hi) return 0;
  for (std::size_t i = 2; i < n; ++i)
    if (b(i) < 0x80 || b(i) > 0xBF) return 0;
  return n;
}

// Every string of `j` (keys too) escaped in place.
void escape_strings(Json& j) {
  if (j.is_string()) {
    const std::string& s = j.get_ref<const std::string&>();
    if (!valid_utf8(s)) j = utf8_escaped(s);
  } else if (j.is_array()) {
    for (Json& e : j) escape_strings(e);
  } else if (j.is_object()) {
    Json out = Json::object();
    for (auto it = j.begin(); it != j.end(); ++it) {
      Json value = it.value();
      escape_strings(value);
      out[utf8_escaped(it.key())] = std::move(value);
    }
    j = std::move(out);
  }
}

constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

}  // namespace

bool valid_utf8(std::string_view text) {
  for (std::size_t at = 0; at < text.size();) {
    const std::size_t n = sequence_length(text, at);
    if (n == 0) return false;
    at += n;
  }
  return true;
}

std::string utf8_escaped(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (std::size_t at = 0; at < text.size();) {
    const std::size_t n = sequence_length(text, at);
    if (n > 0) {
      out.append(text.substr(at, n));
      at += n;
      continue;
    }
    static constexpr char hex[] = "0123456789ABCDEF";
    const auto c = static_cast<unsigned char>(text[at++]);
    out += "\\x";
    out += hex[c >> 4];
    out += hex[c & 15];
  }
  return out;
}

std::string base64(std::string_view bytes) {
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const std::size_t n = std::min<std::size_t>(3, bytes.size() - i);
    std::uint32_t v = 0;
    for (std::size_t k = 0; k < 3; ++k)
      v = (v << 8) | (k < n ? static_cast<unsigned char>(bytes[i + k]) : 0u);
    for (std::size_t k = 0; k < 4; ++k) out += k <= n ? kAlphabet[(v >> (18 - 6 * k)) & 63] : '=';
  }
  return out;
}

std::string from_base64(std::string_view text) {
  if (text.size() % 4 != 0)
    throw Error("base64 text of " + std::to_string(text.size()) +
                " characters (not a multiple of 4)");
  std::array<int, 256> value{};
  value.fill(-1);
  for (int i = 0; i < 64; ++i) value[static_cast<unsigned char>(kAlphabet[i])] = i;
  std::string out;
  for (std::size_t i = 0; i < text.size(); i += 4) {
    std::uint32_t v = 0;
    int pad = 0;
    for (std::size_t k = 0; k < 4; ++k) {
      const auto c = static_cast<unsigned char>(text[i + k]);
      if (c == '=' && i + 4 == text.size() && k >= 2) {
        ++pad;
        v <<= 6;
        continue;
      }
      if (value[c] < 0 || pad > 0) throw Error("malformed base64 text");
      v = (v << 6) | static_cast<std::uint32_t>(value[c]);
    }
    for (int k = 0; k < 3 - pad; ++k) out += static_cast<char>((v >> (16 - 8 * k)) & 255);
  }
  return out;
}

void put_path(Json& j, const std::string& key, const std::string& path) {
  j[key] = utf8_escaped(path);
  if (!valid_utf8(path)) j[key + "_base64"] = base64(path);
}

std::string path_from(const Json& j, const std::string& key) {
  if (auto it = j.find(key + "_base64"); it != j.end() && it->is_string())
    return from_base64(it->get<std::string>());
  if (auto it = j.find(key); it != j.end() && it->is_string()) return it->get<std::string>();
  return "";
}

std::string dump_json(const Json& j, int indent) {
  try {
    return j.dump(indent);
  } catch (const Json::type_error&) {
    Json copy = j;  // a string that is not UTF-8 (rare: escape it, then write)
    escape_strings(copy);
    return copy.dump(indent);
  }
}

}  // namespace spectralize
