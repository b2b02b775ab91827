// The options of a job as data. Each stage declares the options it reads beside its work
// (stage_<name>.cpp, Stage::options); the few settings of no single stage are job_options().
// A front end reads flags, help texts, groups and defaults from these tables and hands every
// value to its option's check and set, so that an option is declared once: apps/tincdt binds
// them to CLI11 without knowing any of them. Rules between options stay in check_options().
#pragma once

#include <cstdint>
#include <iterator>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace tincdt::pipeline {

struct BuildOptions;

enum class OptionKind {
  flag,        // no value: set(options, "")
  value,       // `arity` values (joined by ' ' for set); given again, it is an error
  repeated,    // one value per occurrence, each set in turn ("--clip a.shp --clip b.shp")
  choice,      // one of `words`, any case; set gets the word as written in `words`
  positional,  // the operands (INPUT...), each set in turn
};

struct OptionSpec {
  std::string_view flags = {};       // "-o,--output"; the operands' name for a positional
  std::string_view value_name = {};  // "Z", "FILE.tif"; "" for a flag and a choice (its words)
  std::string_view help = {};        // '\n' where the help breaks the line
  std::string_view group = {};       // the help's heading (option_groups)
  OptionKind kind = OptionKind::value;
  std::span<const std::string_view> words = {};  // a choice's words
  // Shown in the help as the default, and what BuildOptions{} holds (`shown` gives it back);
  // "" when the option is off unless given.
  std::string_view default_text = {};
  unsigned arity = 1;     // values per occurrence (4 for --dem-extent)
  bool required = false;  // the command line cannot do without it
  // "" when TEXT, one value, is acceptable for the option, else why not: "'x' is not a number".
  std::string (*check)(std::string_view text) = nullptr;
  // Stores TEXT, checked, in OPTIONS.
  void (*set)(BuildOptions& options, std::string_view text) = nullptr;
  // The option's value in OPTIONS as the help shows a default (for options with one).
  std::string (*shown)(const BuildOptions& options) = nullptr;

  // The long name ("--output"), else the first: what messages call the option.
  std::string_view name() const;
};

// The help's headings, in the order of the stages their options configure.
namespace option_groups {
inline constexpr std::string_view input = "Input";
inline constexpr std::string_view lines =
    "Surface features (any OGR source: FILE or FILE:LAYER; repeatable)";
inline constexpr std::string_view triangulation = "Triangulation";
inline constexpr std::string_view simplification = "Simplification (after the surface features)";
inline constexpr std::string_view quality = "Quality (after the lines are in, in this order)";
inline constexpr std::string_view boundary =
    "TIN boundary (after --fix-flats and --replace, in this order)";
inline constexpr std::string_view checks = "Checks";
inline constexpr std::string_view output =
    "Output (written together at the end: all of them, or none)";
inline constexpr std::string_view products =
    "Products (from the final TIN: after every step above)";
inline constexpr std::string_view run = "Run";
}  // namespace option_groups

// The settings of every stage (--threads), declared in option_spec.cpp.
std::span<const OptionSpec> job_options();

// ---- for the tables' check and set functions --------------------------------------------------

// A finite number, all of TEXT.
std::optional<double> parse_number(std::string_view text);
// A whole number, all of TEXT.
std::optional<std::uint64_t> parse_count(std::string_view text);
std::string lower(std::string_view text);
// 'TEXT', for a message.
std::string in_quotes(std::string_view text);
// V as the help shows a number: "0", "-9999", "nan".
std::string number_text(double v);
// Checks that refuse with "'TEXT' is not a number" (> 0, >= 0) as their names say.
std::string check_number(std::string_view text);
std::string check_positive(std::string_view text);
std::string check_non_negative(std::string_view text);
// Appends the LAS classification codes of TEXT ("2,8") to CLASSES; returns the first item that
// is not a code (0-255), if any.
std::optional<std::string> append_class_codes(std::string_view text,
                                              std::vector<std::uint8_t>& classes);

// ---- a table's common entries -----------------------------------------------------------------
// A field of BuildOptions by its path: field<&BuildOptions::write, &BuildOptions::Write::gpkg_tin>
// is options.write.gpkg_tin. The set and shown functions below store into one, so that most
// entries need no function of their own.
template <auto... Path>
auto& field(BuildOptions& options) {
  return (options.*....*Path);
}
template <auto... Path>
const auto& field(const BuildOptions& options) {
  return (options.*....*Path);
}

template <auto... Path>
void set_text(BuildOptions& options, std::string_view text) {
  field<Path...>(options) = text;
}
template <auto... Path>
void add_text(BuildOptions& options, std::string_view text) {
  field<Path...>(options).emplace_back(text);
}
template <auto... Path>
void set_true(BuildOptions& options, std::string_view) {
  field<Path...>(options) = true;
}
template <auto... Path>
void set_number(BuildOptions& options, std::string_view text) {
  field<Path...>(options) = *parse_number(text);
}
template <auto... Path>
std::string show_number(const BuildOptions& options) {
  return number_text(field<Path...>(options));
}
// A choice whose word WORDS[i] stands for the value VALUES[i].
template <const auto& Words, const auto& Values, auto... Path>
void set_choice(BuildOptions& options, std::string_view word) {
  static_assert(std::size(Words) == std::size(Values));
  for (std::size_t i = 0; i < std::size(Words); ++i)
    if (word == Words[i]) field<Path...>(options) = Values[i];
}
template <const auto& Words, const auto& Values, auto... Path>
std::string show_choice(const BuildOptions& options) {
  for (std::size_t i = 0; i < std::size(Values); ++i)
    if (field<Path...>(options) == Values[i]) return std::string(Words[i]);
  return {};
}

using OptionSetter = void (*)(BuildOptions& options, std::string_view text);

// A flag (no value) that SET records.
constexpr OptionSpec flag_option(std::string_view flags, std::string_view group, OptionSetter set,
                                 std::string_view help) {
  return {.flags = flags, .help = help, .group = group, .kind = OptionKind::flag, .set = set};
}
// An option of one VALUE_NAME that SET stores unchecked (a path, a name).
constexpr OptionSpec text_option(std::string_view flags, std::string_view value_name,
                                 std::string_view group, OptionSetter set, std::string_view help) {
  return {.flags = flags, .value_name = value_name, .help = help, .group = group, .set = set};
}
// An option of one VALUE_NAME that CHECK accepts before SET stores it.
constexpr OptionSpec checked_option(std::string_view flags, std::string_view value_name,
                                    std::string_view group, std::string (*check)(std::string_view),
                                    OptionSetter set, std::string_view help) {
  OptionSpec spec = text_option(flags, value_name, group, set, help);
  spec.check = check;
  return spec;
}
// SPEC with a default: DEFAULT_TEXT in the help, SHOWN giving back BuildOptions{}'s value.
constexpr OptionSpec with_default(OptionSpec spec, std::string_view default_text,
                                  std::string (*shown)(const BuildOptions&)) {
  spec.default_text = default_text;
  spec.shown = shown;
  return spec;
}
// One of WORDS, stored at PATH as the VALUES[i] of the word given; DEFAULT_WORD is the word of
// BuildOptions{}'s value.
template <const auto& Words, const auto& Values, auto... Path>
constexpr OptionSpec choice_option(std::string_view flags, std::string_view group,
                                   std::string_view default_word, std::string_view help) {
  return {.flags = flags,
          .help = help,
          .group = group,
          .kind = OptionKind::choice,
          .words = Words,
          .default_text = default_word,
          .set = set_choice<Words, Values, Path...>,
          .shown = show_choice<Words, Values, Path...>};
}
// The same, given once or more: SET takes each value in turn.
constexpr OptionSpec repeated_option(std::string_view flags, std::string_view value_name,
                                     std::string_view group, OptionSetter set,
                                     std::string_view help) {
  OptionSpec spec = text_option(flags, value_name, group, set, help);
  spec.kind = OptionKind::repeated;
  return spec;
}

}  // namespace tincdt::pipeline
