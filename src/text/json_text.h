#pragma once
// Text for the JSON that spectralize writes (reports, manifests, summaries): file names on
// Linux are bytes, JSON strings are UTF-8 (docs/DESIGN.md §9). A name that is not valid UTF-8
// is written readably with each stray byte as the four characters \xNN, and losslessly as the
// base64 of its bytes in a second field, "<key>_base64"; a valid name is written as it is,
// without that field. No JSON writer throws on text.

#include <nlohmann/json_fwd.hpp>
#include <string>
#include <string_view>

namespace spectralize {

/// True when `text` is valid UTF-8 (no overlong forms, surrogates or values above U+10FFFF).
/// Cost: O(length).
bool valid_utf8(std::string_view text);

/// `text` with every byte that is not part of a valid UTF-8 sequence written as "\xNN" (two
/// upper-case hex digits); valid UTF-8 is returned unchanged. Cost: O(length).
std::string utf8_escaped(std::string_view text);

/// The standard base64 (RFC 4648, with padding) of `bytes`. Cost: O(length).
std::string base64(std::string_view bytes);

/// The bytes of a standard base64 text; throws Error for malformed text. Cost: O(length).
std::string from_base64(std::string_view text);

/// Sets j[key] to `path` as UTF-8 (utf8_escaped) and, when `path` is not valid UTF-8,
/// j[key + "_base64"] to its bytes in base64. Cost: O(length).
void put_path(nlohmann::ordered_json& j, const std::string& key, const std::string& path);

/// The path a record holds under `key`: from "<key>_base64" when present, else the text.
/// Cost: O(length).
std::string path_from(const nlohmann::ordered_json& j, const std::string& key);

/// j.dump(indent), never throwing on text: any invalid UTF-8 left in a string (a message that
/// quotes a name) is escaped as utf8_escaped does. Cost: O(size of j).
std::string dump_json(const nlohmann::ordered_json& j, int indent = -1);

}  // namespace spectralize
