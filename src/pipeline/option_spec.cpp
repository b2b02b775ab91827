#include "pipeline/option_spec.hpp"

#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>

#include "pipeline/options.hpp"

namespace tincdt::pipeline {

std::string_view OptionSpec::name() const {
  std::string_view rest = flags;
  while (!rest.empty()) {
    const std::size_t comma = rest.find(',');
    const std::string_view one = rest.substr(0, comma);
    if (one.starts_with("--")) return one;
    if (comma == std::string_view::npos) break;
    rest.remove_prefix(comma + 1);
  }
  return flags.substr(0, flags.find(','));
}

std::optional<double> parse_number(std::string_view text) {
  double v = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(v))
    return std::nullopt;
  return v;
}

std::optional<std::uint64_t> parse_count(std::string_view text) {
  std::uint64_t n = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), n);
  if (text.empty() || ec != std::errc() || end != text.data() + text.size()) return std::nullopt;
  return n;
}

std::string lower(std::string_view text) {
  std::string s(text);
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string in_quotes(std::string_view text) {
  std::string s = "'";
  s += text;
  s += '\'';
  return s;
}

std::string number_text(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

std::string check_number(std::string_view text) {
  return parse_number(text) ? std::string() : in_quotes(text) + " is not a number";
}

std::string check_positive(std::string_view text) {
  const auto v = parse_number(text);
  return v && *v > 0 ? std::string() : in_quotes(text) + " is not a number > 0";
}

std::string check_non_negative(std::string_view text) {
  const auto v = parse_number(text);
  return v && *v >= 0 ? std::string() : in_quotes(text) + " is not a number >= 0";
}

std::optional<std::string> append_class_codes(std::string_view text,
                                              std::vector<std::uint8_t>& classes) {
  while (true) {
    const std::size_t comma = text.find(',');
    const std::string_view item = text.substr(0, comma);
    const auto code = parse_count(item);
    if (!code || *code > 255) return std::string(item);
    classes.push_back(static_cast<std::uint8_t>(*code));
    if (comma == std::string_view::npos) return std::nullopt;
    text.remove_prefix(comma + 1);
  }
}

namespace {

constexpr unsigned kMaxThreads = 1024;

std::string check_threads(std::string_view v) {
  const auto n = parse_count(v);
  return n && *n <= kMaxThreads ? std::string() : in_quotes(v) + " is not a thread count (0-1024)";
}

void set_threads(BuildOptions& o, std::string_view v) {
  o.threads = static_cast<unsigned>(*parse_count(v));
}

constexpr OptionSpec kJobOptions[] = {
    with_default(checked_option("--threads", "N", option_groups::run, check_threads, set_threads,
                                "Threads for the parallel stages (reading XYZ and LAZ, Delaunay,\n"
                                "quality, writing the TIN); "
                                "0 = every core"),
                 "0", [](const BuildOptions& o) { return std::to_string(o.threads); }),
};

}  // namespace

std::span<const OptionSpec> job_options() {
  return kJobOptions;
}

}  // namespace tincdt::pipeline
