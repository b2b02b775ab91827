// The option tables the stages declare: complete enough for a front end to bind them without
// knowing any option, and agreeing with BuildOptions{} on the defaults they show.
#include <gtest/gtest.h>

#include <cctype>
#include <set>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "pipeline/build.hpp"
#include "pipeline/option_spec.hpp"
#include "pipeline/stage.hpp"

namespace tincdt::pipeline {
namespace {

std::vector<const OptionSpec*> every_option() {
  std::vector<const OptionSpec*> all;
  for (const Stage* stage : stages())
    for (const OptionSpec& spec : stage->options) all.push_back(&spec);
  for (const OptionSpec& spec : job_options()) all.push_back(&spec);
  return all;
}

// "-o,--output" -> {"-o", "--output"}.
std::vector<std::string> names_of(std::string_view flags) {
  std::vector<std::string> names;
  while (true) {
    const std::size_t comma = flags.find(',');
    names.emplace_back(flags.substr(0, comma));
    if (comma == std::string_view::npos) return names;
    flags.remove_prefix(comma + 1);
  }
}

TEST(OptionTable, EveryOptionHasHelpGroupAndASetter) {
  const std::vector<const OptionSpec*> all = every_option();
  ASSERT_GT(all.size(), 40u);
  for (const OptionSpec* spec : all) {
    SCOPED_TRACE(std::string(spec->flags));
    EXPECT_FALSE(spec->help.empty());
    EXPECT_NE(spec->set, nullptr);
    if (spec->kind == OptionKind::positional) continue;
    EXPECT_FALSE(spec->group.empty());
    EXPECT_TRUE(spec->name().starts_with("--"));
    const bool takes_value = spec->kind != OptionKind::flag && spec->kind != OptionKind::choice;
    EXPECT_EQ(!spec->value_name.empty(), takes_value);
    if (spec->kind == OptionKind::choice) {
      EXPECT_GE(spec->words.size(), 2u);
      for (std::string_view word : spec->words) EXPECT_EQ(lower(word), word);
    }
  }
}

TEST(OptionTable, FlagsAreUnique) {
  std::set<std::string> seen;
  for (const OptionSpec* spec : every_option())
    for (const std::string& name : names_of(spec->flags))
      EXPECT_TRUE(seen.insert(name).second) << name << " is declared twice";
}

// Every default the help shows is what BuildOptions{} holds, and what setting it gives.
TEST(OptionTable, ShownDefaultsAreBuildOptionsDefaults) {
  int defaults = 0;
  for (const OptionSpec* spec : every_option()) {
    if (spec->default_text.empty()) continue;
    SCOPED_TRACE(std::string(spec->flags));
    ++defaults;
    ASSERT_NE(spec->shown, nullptr);
    EXPECT_EQ(spec->shown(BuildOptions{}), spec->default_text);
    if (spec->kind == OptionKind::choice) {
      bool listed = false;
      for (std::string_view word : spec->words) listed |= word == spec->default_text;
      EXPECT_TRUE(listed);
    }
    BuildOptions o;
    if (spec->check != nullptr) {
      EXPECT_EQ(spec->check(spec->default_text), "");
    }
    spec->set(o, spec->default_text);
    EXPECT_EQ(spec->shown(o), spec->default_text);
  }
  EXPECT_GE(defaults, 7);
}

// Each choice's words reach the field, and no other option's shown value changes: the options
// with a shown value bind distinct fields.
TEST(OptionTable, ChoicesBindTheirOwnFields) {
  std::vector<const OptionSpec*> shown;
  for (const OptionSpec* spec : every_option())
    if (spec->shown != nullptr) shown.push_back(spec);
  for (const OptionSpec* spec : every_option()) {
    if (spec->kind != OptionKind::choice || spec->shown == nullptr) continue;
    for (std::string_view word : spec->words) {
      SCOPED_TRACE(std::string(spec->flags) + " " + std::string(word));
      BuildOptions o;
      spec->set(o, word);
      EXPECT_EQ(spec->shown(o), word);
      for (const OptionSpec* other : shown)
        if (other != spec) {
          EXPECT_EQ(other->shown(o), other->shown(BuildOptions{}));
        }
    }
  }
}

TEST(OptionTable, ChecksRefuseWithTheValueAndSetParsesWhatTheyAccept) {
  const auto find = [](std::string_view name) -> const OptionSpec& {
    for (const OptionSpec* spec : every_option())
      if (spec->name() == name) return *spec;
    throw std::runtime_error("no option " + std::string(name));
  };
  EXPECT_EQ(find("--max-error").check("-1"), "'-1' is not a number >= 0");
  EXPECT_EQ(find("--threads").check("2000"), "'2000' is not a thread count (0-1024)");
  EXPECT_EQ(find("--keep-class").check("2,300"), "'300' is not a LAS classification code (0-255)");
  EXPECT_NE(find("--offset").check("1,2"), "");
  EXPECT_EQ(find("--offset").check("-1000,-2000,0"), "");
  BuildOptions o;
  find("--offset").set(o, "-1000,-2000,0.5");
  EXPECT_EQ(o.write.offset.x, -1000);
  EXPECT_EQ(o.write.offset.z, 0.5);
  find("--dem-extent").set(o, "1 2 3 4");
  ASSERT_TRUE(o.dem.extent);
  EXPECT_EQ(o.dem.extent->max_y, 4);
  find("--keep-class").set(o, "2,8");
  EXPECT_EQ(o.filter.keep_classes, (std::vector<std::uint8_t>{2, 8}));
  find("--format").set(o, "landxml");
  EXPECT_EQ(o.write.format, io::TinFormat::landxml);
}

// The help lists the stages by their titles: each names only options that exist.
TEST(OptionTable, StageTitlesNameOnlyDeclaredOptions) {
  std::set<std::string> known;
  for (const OptionSpec* spec : every_option())
    for (const std::string& name : names_of(spec->flags)) known.insert(name);
  for (const Stage* stage : stages()) {
    std::string_view title = stage->title;
    for (std::size_t at = title.find("--"); at != std::string_view::npos;
         at = title.find("--", at + 2)) {
      std::size_t end = at + 2;
      while (end < title.size() &&
             (std::islower(static_cast<unsigned char>(title[end])) || title[end] == '-'))
        ++end;
      EXPECT_TRUE(known.count(std::string(title.substr(at, end - at))))
          << stage->name << ": " << title.substr(at, end - at);
    }
  }
}

}  // namespace
}  // namespace tincdt::pipeline
