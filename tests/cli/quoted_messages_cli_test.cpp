// Names and bytes in messages: file content and names from a plan are quoted, escaped and cut, so
// an error stays one short line of printable text whatever the file holds.
#include <gtest/gtest.h>

#include <cstddef>
#include <string>

#include "support/files.hpp"
#include "support/tincdt_run.hpp"

namespace tincdt::test {
namespace {

const std::string kSample = std::string(TINCDT_SOURCE_DIR) + "/data/sample.las";

// One line of printable ASCII (or UTF-8) ended by a newline: no byte of a file reaches the
// terminal raw.
bool one_printable_line(const std::string& text) {
  if (text.empty() || text.back() != '\n') return false;
  for (std::size_t i = 0; i + 1 < text.size(); ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c < 0x20 || c == 0x7F) return false;
  }
  return true;
}

// S with its first FROM replaced by TO.
std::string replaced(std::string s, const std::string& from, const std::string& to) {
  const std::size_t at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) s.replace(at, from.size(), to);
  return s;
}

// A folder with sample.las, its plan of two tiles, and tile 0 (a binary PLY).
std::string folder_with_a_tile(const std::string& name) {
  const std::string dir = scratch_dir(name);
  spit(dir + "/sample.las", slurp(kSample));
  expect_success(dir, "plan sample.las --tile-size 200 --buffer 20 -o plan.json");
  expect_success(dir, "--plan plan.json --tile 0 -o t0.ply");
  return dir;
}

TEST(QuotedMessagesCli, BinaryTileBytesLabelledAsciiAreEscaped) {
  const std::string dir = folder_with_a_tile("quoted_messages_cli_ascii");
  spit(dir + "/lab.ply",
       replaced(slurp(dir + "/t0.ply"), "format binary_little_endian 1.0", "format ascii 1.0"));
  // tincdt merge lab.ply -o m.ply
  const ShellRun r = run_tincdt(dir, "merge lab.ply -o m.ply");
  EXPECT_EQ(r.exit_code, 1) << r;
  // The token starts with a backslash and byte 0x8F.
  EXPECT_TRUE(has(r, "lab.ply: byte 41 after the header: '\\\\\\x8F\\xC2uPQ\"A")) << r;
  EXPECT_TRUE(has(r, "' is not a number")) << r;
  EXPECT_TRUE(one_printable_line(r.messages)) << r;
  EXPECT_LT(r.messages.size(), 200u) << r;
}

TEST(QuotedMessagesCli, ABadHeaderWordIsEscaped) {
  const std::string dir = folder_with_a_tile("quoted_messages_cli_header");
  spit(dir + "/bad.ply", replaced(slurp(dir + "/t0.ply"), "format binary_little_endian 1.0",
                                  "format bin\001\377ary 1.0"));
  // tincdt merge bad.ply -o m.ply
  const ShellRun r = run_tincdt(dir, "merge bad.ply -o m.ply");
  EXPECT_EQ(r.exit_code, 1) << r;
  EXPECT_TRUE(has(r, "bad.ply: header line 2: format 'bin\\x01\\xFFary' (")) << r;
  EXPECT_TRUE(one_printable_line(r.messages)) << r;
}

TEST(QuotedMessagesCli, AHugeInputNameInAPlanIsCut) {
  const std::string dir = folder_with_a_tile("quoted_messages_cli_long");
  const std::string name = std::string(1000000, 'x') + ".las";
  spit(dir + "/long.json",
       replaced(slurp(dir + "/plan.json"), "\"sample.las\"", "\"" + name + "\""));
  // tincdt --plan long.json --tile 0 -o t.ply
  const ShellRun r = run_tincdt(dir, "--plan long.json --tile 0 -o t.ply");
  EXPECT_EQ(r.exit_code, 1) << r;
  EXPECT_TRUE(has(r, "long.json: tile 0: input 'xxx")) << r;
  EXPECT_TRUE(has(r, "x...xxxx")) << r;
  EXPECT_TRUE(has(r, "xxxx.las' is missing: the plan was made from other inputs")) << r;
  EXPECT_LT(r.messages.size(), 300u) << r.messages.substr(0, 300);
  EXPECT_TRUE(one_printable_line(r.messages)) << r.messages.substr(0, 300);
}

TEST(QuotedMessagesCli, ControlBytesInAPlanNameAreEscaped) {
  const std::string dir = folder_with_a_tile("quoted_messages_cli_control");
  // The name a\x01b<newline>c.las, as JSON escapes it.
  spit(dir + "/ctl.json",
       replaced(slurp(dir + "/plan.json"), "\"sample.las\"", "\"a\\u0001b\\nc.las\""));
  // tincdt --plan ctl.json --tile 0 -o t.ply
  const ShellRun r = run_tincdt(dir, "--plan ctl.json --tile 0 -o t.ply");
  EXPECT_EQ(r.exit_code, 1) << r;
  EXPECT_TRUE(has(r, "input 'a\\x01b\\nc.las' is missing")) << r;
  EXPECT_TRUE(one_printable_line(r.messages)) << r;
}

TEST(QuotedMessagesCli, AControlByteInAPlanFileNameKeepsTheLineWhole) {
  const std::string dir = folder_with_a_tile("quoted_messages_cli_plan_name");
  spit(dir + "/p\nq.json", "{}");
  // tincdt --plan 'p<newline>q.json' --tile 0 -o t.ply
  const ShellRun r = run_tincdt(dir, "--plan 'p\nq.json' --tile 0 -o t.ply");
  EXPECT_EQ(r.exit_code, 1) << r;
  EXPECT_TRUE(has(r, "'p\\nq.json': ")) << r;
  EXPECT_TRUE(one_printable_line(r.messages)) << r;
}

}  // namespace
}  // namespace tincdt::test
