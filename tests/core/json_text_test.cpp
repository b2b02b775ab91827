// json_string, the one JSON string escaper: every character that RFC 8259 requires escaped is,
// and bytes that are not UTF-8 are kept or replaced as asked.
#include "core/json_text.hpp"

#include <gtest/gtest.h>

#include <string>

namespace tincdt {
namespace {

TEST(JsonString, EscapesQuotesBackslashesAndControlCharacters) {
  EXPECT_EQ(json_string(""), R"("")");
  EXPECT_EQ(json_string("plain/é"), R"("plain/é")");
  EXPECT_EQ(json_string("a\"b\\c"), R"("a\"b\\c")");
  EXPECT_EQ(json_string("\b\f\n\r\t"), R"("\b\f\n\r\t")");
  EXPECT_EQ(json_string(std::string("\0\x01\x1f\x7f", 4)), "\"\\u0000\\u0001\\u001f\x7f\"");
}

TEST(JsonString, NonUtf8BytesAreKeptOrReplaced) {
  // A lone continuation byte, a truncated sequence, an overlong form and a UTF-16 surrogate.
  const std::string bad = "\x80|\xC3|\xC0\xAF|\xED\xA0\x80";
  EXPECT_EQ(json_string(bad), "\"" + bad + "\"");
  EXPECT_EQ(json_string(bad, NonUtf8::replace),
            R"("\ufffd|\ufffd|\ufffd\ufffd|\ufffd\ufffd\ufffd")");
  EXPECT_EQ(json_string("é€😀", NonUtf8::replace), R"("é€😀")");
}

}  // namespace
}  // namespace tincdt
