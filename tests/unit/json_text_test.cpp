// Names in JSON (text/json_text.h): UTF-8 checked by RFC 3629's table, stray bytes escaped
// readably, base64 by RFC 4648's test vectors, and a record that round-trips any bytes.

#include "text/json_text.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "spectralize/core/error.h"

namespace spectralize {
namespace {

TEST(JsonText, Utf8IsCheckedByTheStandardsTable) {
  for (const char* ok : {"", "plain", "caf\xc3\xa9", "\xe2\x82\xac", "\xf0\x9f\x8e\xa8",
                         "\xed\x9f\xbf", "\xf4\x8f\xbf\xbf"})
    EXPECT_TRUE(valid_utf8(ok)) << ok;
  // A stray continuation, a cut sequence, overlong forms, a surrogate, above U+10FFFF, 0xFF.
  for (const char* bad :
       {"\x80", "caf\xc3", "\xc0\xaf", "\xe0\x80\xaf", "\xed\xa0\x80", "\xf4\x90\x80\x80", "\xff",
        "a\xfe"
        "b"})
    EXPECT_FALSE(valid_utf8(bad)) << bad;
  EXPECT_EQ(utf8_escaped("wall\xff\xfe_caf\xc3\xa9"), "wall\\xFF\\xFE_caf\xc3\xa9");
  EXPECT_EQ(utf8_escaped("ok"), "ok");
}

TEST(JsonText, Base64FollowsRfc4648) {
  const std::pair<const char*, const char*> vectors[] = {{"", ""},
                                                         {"f", "Zg=="},
                                                         {"fo", "Zm8="},
                                                         {"foo", "Zm9v"},
                                                         {"foob", "Zm9vYg=="},
                                                         {"fooba", "Zm9vYmE="},
                                                         {"foobar", "Zm9vYmFy"}};
  for (const auto& [plain, coded] : vectors) {
    EXPECT_EQ(base64(plain), coded);
    EXPECT_EQ(from_base64(coded), plain);
  }
  for (const char* bad : {"Zm9", "Zm9v!", "Z===", "=Zm9"}) {
    EXPECT_THROW(from_base64(bad), Error);
  }
}

TEST(JsonText, AnyNameRoundTripsThroughARecord) {
  std::string every;
  for (int c = 1; c < 256; ++c) every += static_cast<char>(c);
  for (const std::string& name : {std::string("lib/a.png"), std::string("lib/\xff.png"), every}) {
    nlohmann::ordered_json j;
    put_path(j, "input", name);
    const std::string text = dump_json(j);
    const auto back = nlohmann::ordered_json::parse(text);  // strict: valid UTF-8
    EXPECT_EQ(path_from(back, "input"), name);
    EXPECT_EQ(back.contains("input_base64"), !valid_utf8(name));
  }
  // A message quoting a stray byte never makes a writer throw.
  nlohmann::ordered_json j;
  j["message"] = std::string("'x\xff.png': no such file");
  EXPECT_EQ(nlohmann::ordered_json::parse(dump_json(j))["message"], "'x\\xFF.png': no such file");
}

}  // namespace
}  // namespace spectralize
