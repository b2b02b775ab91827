#include "core/quoted_text.hpp"

#include <gtest/gtest.h>

#include <string>

namespace tincdt {
namespace {

TEST(QuotedText, PrintableTextIsQuotedAsItIs) {
  EXPECT_EQ(quoted_text("binary"), "'binary'");
  EXPECT_EQ(quoted_text(""), "''");
  EXPECT_EQ(quoted_text("h\xC3\xB6he"), "'h\xC3\xB6he'");  // UTF-8 is kept
}

TEST(QuotedText, ControlAndBrokenBytesAreEscaped) {
  EXPECT_EQ(quoted_text("a\x01"
                        "b\nc.las"),
            "'a\\x01b\\nc.las'");
  EXPECT_EQ(quoted_text("bin\001\377ary"), "'bin\\x01\\xFFary'");
  EXPECT_EQ(quoted_text("\x8F\xC2uPQ\t\r"), "'\\x8F\\xC2uPQ\\t\\r'");
  EXPECT_EQ(quoted_text(std::string("a\0b", 3)), "'a\\x00b'");
  EXPECT_EQ(quoted_text("\xE2\x82"), "'\\xE2\\x82'");  // a UTF-8 sequence cut short
  EXPECT_EQ(quoted_text("\\\x8F"), "'\\\\\\x8F'");     // a backslash is no escape
}

TEST(QuotedText, LongTextKeepsItsStartAndEnd) {
  const std::string name = "/data/" + std::string(1000000, 'x') + "/tile_7.las";
  const std::string shown = quoted_text(name);
  EXPECT_EQ(shown.rfind("'/data/xxx", 0), 0u);
  EXPECT_NE(shown.find("..."), std::string::npos);
  EXPECT_EQ(shown.substr(shown.size() - 12), "/tile_7.las'");
  EXPECT_EQ(shown.size(), 1 + 80 + 1);  // 80 columns between the quotes, "..." among them
  EXPECT_EQ(quoted_text(std::string(80, 'a')), "'" + std::string(80, 'a') + "'");
  EXPECT_NE(quoted_text(std::string(81, 'a')), "'" + std::string(81, 'a') + "'");
}

TEST(QuotedText, EscapesCountInTheLength) {
  const std::string shown = quoted_text(std::string(1000, '\x01'), 20);
  EXPECT_LE(shown.size(), 1 + 20 + 1);
  EXPECT_EQ(shown.find('\x01'), std::string::npos);
  EXPECT_EQ(shown.find("\\x0..."), std::string::npos);  // no escape is cut in two
}

TEST(QuotedText, NamesAreQuotedOnlyWhenTheyNeedIt) {
  EXPECT_EQ(name_text("tiles/t0.ply"), "tiles/t0.ply");
  EXPECT_EQ(name_text("caf\xC3\xA9.las"), "caf\xC3\xA9.las");
  EXPECT_EQ(name_text("a\nb"), "'a\\nb'");
  EXPECT_LT(name_text(std::string(100000, 'n')).size(), 200u);
}

}  // namespace
}  // namespace tincdt
