// The words of a command line before CLI11 reads them: the GDAL spellings that users of GDAL
// type out of habit read as tincdt's options (or refused, saying what to use), and a misspelt
// long option refused with the nearest one declared, instead of a bare "not expected".
#pragma once

#include <CLI/CLI.hpp>

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace tincdt::cli {

// ARGV's words after the program name, with the words -a_srs, -t_srs and -co (exactly these,
// before any "--") as --a-srs, --t-srs and --dem-co. Throws UsageError for -of, GDAL's raster
// format, which CLI11 would otherwise read as -o f.
std::vector<std::string> with_gdal_words(int argc, char** argv);

// ARGV's words after the program name, as they are.
std::vector<std::string> words_of(int argc, char** argv);

// The usage message for the first word of WORDS that looks like a long option ("--name" or
// "--name=value", before any "--") and that APP does not declare, naming the declared option it
// is nearest to when one is near; nullopt when every such word is declared.
std::optional<std::string> unknown_long_option(const CLI::App& app,
                                               const std::vector<std::string>& words);

// The edit distance between A and B: insertions, deletions, substitutions and swaps of two
// neighbouring characters, each counting 1.
std::size_t edit_distance(std::string_view a, std::string_view b);

// Parses WORDS (the words after the program name) into APP.
void parse_words(CLI::App& app, std::vector<std::string> words);

}  // namespace tincdt::cli
