// SPDX-License-Identifier: MIT
// JsonObject's strings go through nlohmann-json: control characters escaped, bytes that are not UTF-8 (a Latin-1
// file name) replaced by U+FFFD, so the output is always valid UTF-8 and valid JSON (issue 23, item 10).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "dualgraph/frontend/io/json_writer.h"

namespace dualgraph {
namespace {

/// Whether `text` is well-formed UTF-8 (no stray continuation bytes, no truncated or overlong sequences).
bool validUtf8(const std::string& text) {
  for (size_t i = 0; i < text.size();) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    const int length = c < 0x80 ? 1 : (c >> 5) == 0x6 ? 2 : (c >> 4) == 0xE ? 3 : (c >> 3) == 0x1E ? 4 : 0;
    if (length == 0 || (length == 2 && c < 0xC2) || i + static_cast<size_t>(length) > text.size()) return false;
    for (int k = 1; k < length; ++k) {
      if ((static_cast<unsigned char>(text[i + static_cast<size_t>(k)]) >> 6) != 0x2) return false;
    }
    i += static_cast<size_t>(length);
  }
  return true;
}

TEST(JsonWriter, StringsAreEscapedAndBytesThatAreNotUtf8Replaced) {
  const std::string latin1_path = "/flights/caf\xe9/run";  // 'é' in Latin-1: one byte 0xE9, not UTF-8
  JsonObject json;
  json.add("sequence", latin1_path).add("note", std::string("tab\there \"quoted\"\n\x01")).add("ok", std::string("ça va"));
  const std::string text = json.str();
  EXPECT_TRUE(validUtf8(text)) << text;
  EXPECT_NE(text.find("\"sequence\": \"/flights/caf\xEF\xBF\xBD/run\""), std::string::npos) << text;  // U+FFFD
  EXPECT_NE(text.find("\"note\": \"tab\\there \\\"quoted\\\"\\n\\u0001\""), std::string::npos) << text;
  EXPECT_NE(text.find("\"ok\": \"ça va\""), std::string::npos) << text;  // valid UTF-8 kept as it is
  EXPECT_FALSE(validUtf8(latin1_path));  // the check itself can fail
}

TEST(JsonWriter, NumbersAsBeforeAndNonFiniteAsNull) {
  JsonObject json;
  json.add("x", 0.1).add("n", 3L).add("bad", std::nan("")).add("yes", true);
  EXPECT_EQ(json.str(), "{\"x\": 0.10000000000000001, \"n\": 3, \"bad\": null, \"yes\": true}");
}

}  // namespace
}  // namespace dualgraph
