#include "command_words.hpp"

#include <algorithm>
#include <utility>

#include "core/error.hpp"

namespace tincdt::cli {
namespace {

// GDAL's spellings of tincdt's options, word for word.
constexpr std::pair<std::string_view, std::string_view> kGdalWords[] = {
    {"-a_srs", "--a-srs"},
    {"-t_srs", "--t-srs"},
    {"-co", "--dem-co"},
    {"-of", "--dem-format"},  // else "-of GTiff" would read as "-o f GTiff"
};

// The declared long option nearest to NAME (without its dashes), when it is near enough to be
// what was meant: a unique one NAME begins, or one within 2 edits (and fewer than half of
// NAME's letters) of it.
std::optional<std::string> nearest(const std::vector<std::string>& names, std::string_view name) {
  std::vector<std::string> starting;
  for (const std::string& n : names)
    if (n.size() > name.size() && n.compare(0, name.size(), name) == 0) starting.push_back(n);
  if (starting.size() == 1) return starting.front();
  std::optional<std::string> best;
  std::size_t best_distance = 3;
  for (const std::string& n : names) {
    const std::size_t d = edit_distance(name, n);
    if (d < best_distance && 2 * d < name.size()) {
      best = n;
      best_distance = d;
    }
  }
  return best;
}

}  // namespace

std::vector<std::string> words_of(int argc, char** argv) {
  return argc > 1 ? std::vector<std::string>(argv + 1, argv + argc) : std::vector<std::string>{};
}

std::vector<std::string> with_gdal_words(int argc, char** argv) {
  std::vector<std::string> words = words_of(argc, argv);
  for (std::string& word : words) {
    if (word == "--") break;
    for (const auto& [gdal, ours] : kGdalWords)
      if (word == gdal) word = ours;
  }
  return words;
}

std::optional<std::string> unknown_long_option(const CLI::App& app,
                                               const std::vector<std::string>& words) {
  std::vector<std::string> names;
  for (const CLI::Option* option : app.get_options())
    for (const std::string& name : option->get_lnames()) names.push_back(name);
  for (const std::string& word : words) {
    if (word == "--") break;
    if (word.size() < 3 || word.compare(0, 2, "--") != 0) continue;
    const std::string name = word.substr(2, word.find('=') - 2);
    if (std::find(names.begin(), names.end(), name) != names.end()) continue;
    std::string message = "unknown option --" + name;
    if (const auto near = nearest(names, name)) message += "; did you mean --" + *near + "?";
    return message;
  }
  return std::nullopt;
}

std::size_t edit_distance(std::string_view a, std::string_view b) {
  // Three rows of the optimal string alignment table: i - 2, i - 1 and i.
  std::vector<std::size_t> before(b.size() + 1), last(b.size() + 1), row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) last[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
      row[j] = std::min({last[j] + 1, row[j - 1] + 1, last[j - 1] + cost});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        row[j] = std::min(row[j], before[j - 2] + 1);
    }
    std::swap(before, last);
    std::swap(last, row);
  }
  return last[b.size()];
}

void parse_words(CLI::App& app, std::vector<std::string> words) {
  std::reverse(words.begin(), words.end());  // CLI11 takes them last first
  app.parse(words);
}

}  // namespace tincdt::cli
