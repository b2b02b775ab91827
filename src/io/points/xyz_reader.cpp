// XYZ text reader: one point per line, numbers separated by blanks, commas or semicolons, an
// optional header line naming the columns, '#' comments. A bad line is an error naming the line,
// never a silent 0.
//
// The text is memory-mapped (or read from stdin in large blocks) and parsed with std::from_chars,
// in windows of a few tens of MB. Each window is cut at newlines into one piece per core; the
// pieces are parsed in parallel and appended in order, and the window's pages are then handed back
// to the kernel, so resident memory stays near the size of the points, not of the text. A stream
// is read through one buffer of fixed size: a line longer than kMaxLineBytes is an error, so no
// input (/dev/zero, a binary file) makes it grow.

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <exception>
#include <memory>
#include <new>
#include <string>
#include <string_view>
#include <vector>

#include "core/coordinates.hpp"
#include "core/error.hpp"
#include "core/number_text.hpp"
#include "core/parallel.hpp"
#include "core/quoted_text.hpp"
#include "io/mapped_file.hpp"
#include "io/points/point_reader.hpp"
#include "io/points/point_selection.hpp"

namespace tincdt::io {
namespace {

constexpr std::size_t kPieceBytes = std::size_t{32} << 20;  // per thread and window
constexpr std::size_t kMinPieceBytes = std::size_t{1} << 20;
constexpr unsigned kMaxThreads = 8;
// A text line of x y z and a few more columns takes tens of bytes; one of a megabyte is binary
// data or a file without line ends, and would otherwise be buffered whole.
constexpr std::size_t kMaxLineBytes = std::size_t{1} << 20;
static_assert(kMaxLineBytes < kPieceBytes, "a stream buffer holds a whole line of maximal length");

// How the columns of the file are laid out.
struct Layout {
  char delimiter = 0;         // ',' or ';'; 0 = runs of blanks
  int column[3] = {0, 1, 2};  // x, y, z
  int last_column = 2;
  int class_column = -1;  // a header's "classification" or "class" column; -1 when none
  // With a class filter: the classes kept (indexed by code), read from class_column.
  const std::array<bool, 256>* class_kept = nullptr;
};

bool is_blank(char c) {
  return c == ' ' || c == '\t' || c == '\r';
}

const char* skip_blanks(const char* p, const char* end) {
  while (p < end && is_blank(*p)) ++p;
  return p;
}

// The end of the field starting at P.
const char* field_end(const char* p, const char* end, char delimiter) {
  while (p < end && !is_blank(*p) && *p != delimiter) ++p;
  return p;
}

// from_chars, plus a leading '+' that some writers emit.
std::from_chars_result parse_double(const char* p, const char* end, double& value) {
  if (p < end && *p == '+' && p + 1 < end && p[1] != '-' && p[1] != '+') ++p;
  return std::from_chars(p, end, value);
}

enum class Problem {
  kNone,
  kTooFewFields,
  kEmptyField,
  kNotANumber,
  kNotFinite,
  kOutOfRange,
  kNoDelimiter,
  kBareCr,
  kTooLong,
  kBadClass
};

// Where the first bad line of a piece is, and what is wrong with it.
struct Failure {
  Problem problem = Problem::kNone;
  std::size_t line_index = 0;  // 0-based, within the piece
  const char* line = nullptr;
  const char* line_end = nullptr;
  const char* field = nullptr;
  const char* field_end = nullptr;
  int column = 0;
};

struct PieceResult {
  std::size_t lines = 0;
  std::size_t points = 0;  // data lines, kept or not
  Failure failure;
  std::exception_ptr exception;  // e.g. bad_alloc, rethrown by the caller
};

// Parses the fields of one line [p, eol) that is not blank or a comment. Returns kNone and the
// point, or the problem and the field at fault.
// CLS: the class code, when the layout reads one.
Problem parse_line(const char* p, const char* eol, const Layout& layout, Point3& point,
                   unsigned& cls, Failure& where) {
  double v[4] = {0, 0, 0, 0};
  const int class_column = layout.class_kept != nullptr ? layout.class_column : -1;
  for (int col = 0;; ++col) {
    const int slot = layout.column[0] == col   ? 0
                     : layout.column[1] == col ? 1
                     : layout.column[2] == col ? 2
                     : class_column == col     ? 3
                                               : -1;
    const char* end;
    if (slot >= 0) {
      const auto [next, ec] = parse_double(p, eol, v[slot]);
      end = next;
      // The number must fill the field: "3.5abc" or "1,5" (decimal comma) is not a number.
      const bool whole = ec == std::errc() && (next == eol || is_blank(*next) ||
                                               (*next == layout.delimiter && *next != 0));
      const bool good = slot == 3 ? v[3] >= 0 && v[3] <= 255 && v[3] == std::floor(v[3])
                                  : coordinate_in_range(v[slot]);
      if (!whole || !good) {
        where.field = p;
        where.field_end = field_end(p, eol, layout.delimiter);
        where.column = col;
        if (p == where.field_end) {
          return p == eol ? Problem::kTooFewFields : Problem::kEmptyField;
        }
        if (slot == 3) return Problem::kBadClass;
        if (!whole) return Problem::kNotANumber;
        return std::isfinite(v[slot]) ? Problem::kOutOfRange : Problem::kNotFinite;
      }
    } else {
      end = field_end(p, eol, layout.delimiter);
    }
    if (col == layout.last_column) {
      // Columns after the last one used are ignored, but not a carriage return followed by more
      // text: that is the next line of a file with CR-only line ends. (CR LF is the one check.)
      const char* q = end;
      while (q < eol && (*q == ' ' || *q == '\t')) ++q;
      if (q < eol && *q == '\r') {
        while (q < eol && *q == '\r') ++q;
        if (q < eol) return Problem::kBareCr;
      }
      break;
    }
    // Step over the separator to the next field.
    p = skip_blanks(end, eol);
    if (layout.delimiter != 0) {
      if (p == eol) {
        where.field = where.field_end = eol;
        return Problem::kTooFewFields;
      }
      if (*p != layout.delimiter) {
        where.field = p;
        where.field_end = field_end(p, eol, layout.delimiter);
        where.column = col + 1;
        return Problem::kNoDelimiter;
      }
      p = skip_blanks(p + 1, eol);
    } else if (p == eol) {
      where.field = where.field_end = eol;
      return Problem::kTooFewFields;
    }
  }
  point = without_signed_zero(Point3{v[0], v[1], v[2]});
  cls = static_cast<unsigned>(v[3]);
  return Problem::kNone;
}

// The end of the line that starts at P: its '\n', or E when it has none.
const char* line_end(const char* p, const char* e) {
  const auto* nl = static_cast<const char*>(std::memchr(p, '\n', static_cast<std::size_t>(e - p)));
  return nl != nullptr ? nl : e;
}

// Where the line after the one that ends at EOL starts (E when there is none).
const char* next_line(const char* eol, const char* e) {
  return eol != e ? eol + 1 : e;
}

bool too_long(const char* line, const char* eol) {
  return static_cast<std::size_t>(eol - line) > kMaxLineBytes;
}

// Parses the whole lines in [b, e) (e is just past a '\n' or the end of the input), appending
// the points to OUT. Stops at the first bad line.
void parse_piece(const char* b, const char* e, const Layout& layout, std::vector<Point3>& out,
                 PieceResult& result) {
  try {
    const char* p = b;
    while (p < e) {
      const char* eol = line_end(p, e);
      if (too_long(p, eol)) {
        result.failure = {Problem::kTooLong, result.lines, p, eol, p, eol, 0};
        return;
      }
      const char* q = skip_blanks(p, eol);
      if (q != eol && *q != '#') {
        Point3 point;
        unsigned cls = 0;
        Failure& f = result.failure;
        f.problem = parse_line(q, eol, layout, point, cls, f);
        if (f.problem != Problem::kNone) {
          f.line_index = result.lines;
          f.line = p;
          f.line_end = eol;
          return;
        }
        ++result.points;
        if (layout.class_kept == nullptr || (*layout.class_kept)[cls]) out.push_back(point);
      }
      ++result.lines;
      p = next_line(eol, e);
    }
  } catch (...) {
    result.exception = std::current_exception();
  }
}

// A line or field for a message, quoted: without its carriage returns, any byte that is not
// printable text escaped (a binary file's bytes never reach the terminal), at most 60 characters.
std::string quote(const char* b, const char* e) {
  std::string text(b, e);
  std::erase(text, '\r');
  return quoted_text(text, 60);
}

// Text with carriage returns in it, not binary data (which holds other control bytes).
bool has_cr(const char* b, const char* e) {
  bool cr = false;
  for (const char* p = b; p < e; ++p) {
    const auto c = static_cast<unsigned char>(*p);
    if (c == '\r') cr = true;
    if (c < 0x20 && c != '\r' && c != '\n' && c != '\t') return false;
  }
  return cr;
}

const char* const kCrOnlyAdvice =
    "the file has CR-only line ends (classic Mac OS), so it reads as one line; convert them to "
    "LF, e.g. with tr '\\r' '\\n'";

[[noreturn]] void throw_too_long(const std::string& name, std::size_t line_number, bool cr) {
  throw InputError(name, "line " + count_text(line_number),
                   "longer than " + count_text(kMaxLineBytes) + " bytes: " +
                       (cr ? std::string(kCrOnlyAdvice)
                           : std::string("not XYZ text (binary data, or no line ends)")));
}

[[noreturn]] void throw_bad_line(const std::string& name, std::size_t line_number, const Failure& f,
                                 char delimiter) {
  if (f.problem == Problem::kTooLong) {
    throw_too_long(name, line_number, has_cr(f.line, f.line + kMaxLineBytes));
  }
  if (f.problem == Problem::kBareCr) {
    throw InputError(name, "line " + count_text(line_number),
                     "a carriage return (CR) inside the line: " + std::string(kCrOnlyAdvice));
  }
  std::string why;
  const std::string field = quote(f.field, f.field_end);
  switch (f.problem) {
    case Problem::kTooFewFields:
      why = "too few fields";
      break;
    case Problem::kEmptyField:
      why = "field " + count_text(f.column + 1) + " is empty";
      break;
    case Problem::kNotANumber:
      why = field + " is not a number";
      break;
    case Problem::kNotFinite:
      why = field + " is not a finite number";
      break;
    case Problem::kOutOfRange:
      why = field + " is beyond +-" + kMaxCoordinateText +
            ", the coordinate range tincdt computes with; wrong units or a corrupt value?";
      break;
    case Problem::kNoDelimiter:
      why = std::string("no '") + delimiter + "' before " + field;
      break;
    case Problem::kBadClass:
      why = field + " is not a class code (0 to 255)";
      break;
    case Problem::kNone:
    case Problem::kBareCr:
    case Problem::kTooLong:
      break;
  }
  throw InputError(name, "line " + count_text(line_number),
                   "expected 3 numbers x y z, got " + quote(f.line, f.line_end) + " (" + why + ")");
}

std::string lower_unquoted(std::string_view s) {
  while (!s.empty() && (s.front() == '"' || s.front() == '\'')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == '"' || s.back() == '\'')) s.remove_suffix(1);
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

// Where the data starts: past a UTF-8 byte-order mark, leading comments and blank lines, and the
// header line if there is one; plus the column layout. `found` is false when [b, e) holds no
// complete data line yet and more input may follow; `data` is then where the incomplete line
// starts. `problem` (kTooLong, kBareCr) is a line before the data that cannot be read.
struct Start {
  bool found = false;
  Layout layout;
  const char* data = nullptr;
  std::size_t lines_before = 0;  // lines before `data` (and before the line with a problem)
  Problem problem = Problem::kNone;
  const char* problem_line = nullptr;
};

// A carriage return followed by more text in [b, e): CR-only line ends.
bool has_bare_cr(const char* b, const char* e) {
  for (const char* p = b; (p = static_cast<const char*>(std::memchr(
                               p, '\r', static_cast<std::size_t>(e - p)))) != nullptr;) {
    while (p < e && *p == '\r') ++p;
    if (p < e) return true;
  }
  return false;
}

Start find_start(const char* b, const char* e, bool at_eof) {
  Start s;
  if (e - b >= 3 && std::memcmp(b, "\xEF\xBB\xBF", 3) == 0) b += 3;
  const char* p = b;
  while (p < e) {
    const char* eol = line_end(p, e);
    if (too_long(p, eol)) {
      s.problem = Problem::kTooLong;
      s.problem_line = p;
      return s;
    }
    if (eol == e && !at_eof) {  // the line may go on in the next block
      s.data = p;
      return s;
    }
    const char* next = next_line(eol, e);
    if (has_bare_cr(p, eol)) {
      s.problem = Problem::kBareCr;
      s.problem_line = p;
      return s;
    }
    const char* q = skip_blanks(p, eol);
    if (q == eol || *q == '#') {
      ++s.lines_before;
      p = next;
      continue;
    }
    // The separator: ';' if the line has one, else ',' if it has one, else blanks (a comment at
    // the end of the line does not count).
    std::string_view line(q, static_cast<std::size_t>(eol - q));
    line = line.substr(0, line.find('#'));
    if (line.find(';') != std::string_view::npos) {
      s.layout.delimiter = ';';
    } else if (line.find(',') != std::string_view::npos) {
      s.layout.delimiter = ',';
    }
    // A header is a first line whose first field does not even start like a number.
    double ignored = 0;
    const bool numeric = parse_double(q, eol, ignored).ec == std::errc() ||
                         (*q != '\0' && std::strchr("0123456789+-.", *q) != nullptr);
    s.found = true;
    s.data = p;
    if (numeric) return s;
    int column[3] = {-1, -1, -1};
    const char* f = q;
    for (int col = 0; f < eol; ++col) {
      const char* fe = f;
      if (s.layout.delimiter != 0) {
        while (fe < eol && *fe != s.layout.delimiter) ++fe;
      } else {
        fe = field_end(f, eol, 0);
      }
      const char* trimmed_end = fe;
      while (trimmed_end > f && is_blank(trimmed_end[-1])) --trimmed_end;
      const std::string name = lower_unquoted({f, static_cast<std::size_t>(trimmed_end - f)});
      for (int k = 0; k < 3; ++k) {
        if (name.size() == 1 && name[0] == "xyz"[k] && column[k] < 0) column[k] = col;
      }
      if ((name == "classification" || name == "class") && s.layout.class_column < 0)
        s.layout.class_column = col;
      f = skip_blanks(fe < eol && *fe == s.layout.delimiter ? fe + 1 : fe, eol);
    }
    if (column[0] >= 0 && column[1] >= 0 && column[2] >= 0) {
      std::copy(column, column + 3, s.layout.column);
      s.layout.last_column = std::max({column[0], column[1], column[2]});
    }
    s.data = next;
    ++s.lines_before;
    return s;
  }
  s.found = at_eof;
  s.data = e;
  return s;
}

// A line before the data that find_start could not read; LINE is its number.
[[noreturn]] void throw_start_problem(const std::string& name, std::size_t line,
                                      const Start& start) {
  if (start.problem == Problem::kTooLong) {
    throw_too_long(name, line, has_cr(start.problem_line, start.problem_line + kMaxLineBytes));
  }
  throw InputError(name, "line " + count_text(line),
                   "a carriage return (CR) inside the line: " + std::string(kCrOnlyAdvice));
}

// THREADS, or every core for 0, at most kMaxThreads.
unsigned parser_threads(unsigned threads) {
  return static_cast<unsigned>(std::min<std::size_t>(thread_count(threads), kMaxThreads));
}

// Parses the whole lines of [b, e), cut into up to THREADS pieces at newlines, and appends the
// points in file order. LINES_BEFORE counts the lines of the input before b and is advanced.
// Adds the points read and the points appended (those the class filter keeps) to STATS.
void parse_window(const std::string& name, const char* b, const char* e, const Layout& layout,
                  unsigned threads, std::size_t& lines_before, std::vector<Point3>& out,
                  std::vector<std::vector<Point3>>& scratch, PointReadStats& stats) {
  const auto bytes = static_cast<std::size_t>(e - b);
  const std::size_t pieces =
      std::clamp<std::size_t>(bytes / kMinPieceBytes, 1, std::max(1u, threads));
  std::vector<const char*> cut(pieces + 1, e);
  cut[0] = b;
  for (std::size_t i = 1; i < pieces; ++i) {
    const char* guess = std::max(cut[i - 1], b + bytes / pieces * i);
    cut[i] = next_line(line_end(guess, e), e);
  }
  if (scratch.size() < pieces) scratch.resize(pieces);
  std::vector<PieceResult> results(pieces);
  const std::size_t before = out.size();
  parallel_chunks(
      pieces, pieces,
      [&](std::size_t first, std::size_t last) {
        for (std::size_t i = first; i < last; ++i) {
          if (i == 0) {
            parse_piece(cut[0], cut[1], layout, out, results[0]);  // straight into `out`
          } else {
            scratch[i].clear();
            parse_piece(cut[i], cut[i + 1], layout, scratch[i], results[i]);
          }
        }
      },
      1);
  for (std::size_t i = 0; i < pieces; ++i) {
    const PieceResult& r = results[i];
    if (r.exception) std::rethrow_exception(r.exception);
    if (r.failure.problem != Problem::kNone) {
      throw_bad_line(name, lines_before + r.failure.line_index + 1, r.failure, layout.delimiter);
    }
    if (i > 0) out.insert(out.end(), scratch[i].begin(), scratch[i].end());
    lines_before += r.lines;
    stats.points_read += r.points;
  }
  stats.points_kept += out.size() - before;
}

// The layout with the class filter of SEL: the class column read and the classes kept. Throws
// when SEL filters classes but the text has no class column.
Layout with_filter(const std::string& name, Layout layout, const detail::Selection& sel) {
  if (!sel.filter_classes) return layout;
  if (layout.class_column < 0) {
    throw InputError(name, "",
                     "the XYZ text has no classification column (a header line naming a "
                     "'classification' or 'class' column), so no class can be kept or dropped",
                     Remedy::class_filter);
  }
  layout.class_kept = &sel.class_kept;
  layout.last_column = std::max(layout.last_column, layout.class_column);
  return layout;
}

// Reserves room for the points of a SIZE-byte text, judging the line length from its first MB.
void reserve_for(const char* b, std::size_t size, std::vector<Point3>& out) {
  const std::size_t sample = std::min(size, kMinPieceBytes);
  const auto newlines = static_cast<std::size_t>(std::count(b, b + sample, '\n'));
  if (sample == size) {
    out.reserve(out.size() + newlines + 1);
    return;
  }
  const double per_line =
      static_cast<double>(sample) / static_cast<double>(std::max<std::size_t>(newlines, 1));
  out.reserve(out.size() + static_cast<std::size_t>(static_cast<double>(size) / per_line * 1.01) +
              16);
  detail::advise_huge_pages(out);
}

PointReadStats read_mapped(const std::string& path, const detail::Selection& sel,
                           std::vector<Point3>& out, unsigned threads_wanted) {
  const detail::MappedFile file(path);
  if (file.size() == 0) throw InputError(path, "", "empty file");
  const char* const b = file.chars();
  const char* const e = b + file.size();
  file.advise_sequential(0, file.size());
  const Start start = find_start(b, e, true);
  if (start.problem != Problem::kNone) throw_start_problem(path, start.lines_before + 1, start);
  const Layout layout = with_filter(path, start.layout, sel);
  PointReadStats stats;
  stats.format = "xyz";
  reserve_for(start.data, static_cast<std::size_t>(e - start.data), out);
  const unsigned threads = parser_threads(threads_wanted);
  const std::size_t window = kPieceBytes * threads;
  std::vector<std::vector<Point3>> scratch;
  std::size_t lines = start.lines_before;
  const char* p = start.data;
  while (p < e) {
    const char* w = p + std::min(window, static_cast<std::size_t>(e - p));
    if (w < e) {  // end the window after a newline
      w = next_line(line_end(w, e), e);
    }
    parse_window(path, p, w, layout, threads, lines, out, scratch, stats);
    file.release(static_cast<std::size_t>(p - b), static_cast<std::size_t>(w - b));
    p = w;
  }
  return stats;
}

PointReadStats read_stream(int fd, const std::string& name, const detail::Selection& sel,
                           std::vector<Point3>& out, unsigned threads_wanted) {
  const unsigned threads = parser_threads(threads_wanted);
  // The buffer starts small (stdin often holds a few lines) and doubles each time the input
  // fills it, up to one window of parallel parsing: larger than kMaxLineBytes, so that a full
  // buffer always holds a line end or an over-long line.
  const std::size_t max_capacity = kPieceBytes * threads;
  std::size_t capacity = std::size_t{1} << 16;
  std::unique_ptr<char[]> buffer(new char[capacity]);
  bool was_full = false;
  std::size_t filled = 0;
  bool eof = false;
  bool any_input = false;
  bool started = false;
  Layout layout;
  std::size_t lines = 0;
  std::vector<std::vector<Point3>> scratch;
  PointReadStats stats;
  stats.format = "xyz";
  while (!eof || filled > 0) {
    if (was_full && capacity < max_capacity) {
      capacity *= 2;
      std::unique_ptr<char[]> bigger(new char[capacity]);
      std::memcpy(bigger.get(), buffer.get(), filled);
      buffer = std::move(bigger);
    }
    while (!eof && filled < capacity) {
      const ssize_t n = ::read(fd, buffer.get() + filled, capacity - filled);
      if (n < 0) {
        if (errno == EINTR) continue;
        throw InputError(name, "", std::string("read failed: ") + std::strerror(errno));
      }
      if (n == 0) eof = true;
      filled += static_cast<std::size_t>(n);
      if (n > 0) any_input = true;
    }
    was_full = filled == capacity;
    const char* b = buffer.get();
    const char* e = b + filled;
    if (!started) {
      const Start start = find_start(b, e, eof);
      if (start.problem != Problem::kNone)
        throw_start_problem(name, lines + start.lines_before + 1, start);
      lines += start.lines_before;
      // Drop the leading comments (and the header) so that the buffer starts with the line
      // that is still incomplete, or with the data.
      filled = static_cast<std::size_t>(e - start.data);
      std::memmove(buffer.get(), start.data, filled);
      e = b + filled;
      if (!start.found) continue;  // no complete first data line yet: read more
      started = true;
      layout = with_filter(name, start.layout, sel);
    }
    // Parse up to the last newline (everything, at the end of the input).
    const char* cut = e;
    if (!eof) {
      while (cut > b && cut[-1] != '\n') --cut;
    }
    if (cut > b) parse_window(name, b, cut, layout, threads, lines, out, scratch, stats);
    const auto rest = static_cast<std::size_t>(e - cut);
    if (rest > kMaxLineBytes) throw_too_long(name, lines + 1, has_cr(cut, cut + kMaxLineBytes));
    std::memmove(buffer.get(), cut, rest);
    filled = rest;
  }
  if (!any_input) throw InputError(name, "", "empty input");
  return stats;
}

}  // namespace

PointReadStats read_xyz(const std::string& path, std::vector<Point3>& out, unsigned threads) {
  return read_xyz(path, PointFilter{}, out, threads);
}

PointReadStats read_xyz(const std::string& path, const PointFilter& filter,
                        std::vector<Point3>& out, unsigned threads) {
  const std::string name = path == "-" ? "<stdin>" : path;
  const detail::Selection sel(filter);
  if (sel.first_only || sel.last_only) {
    throw InputError(name, "",
                     "XYZ text has no return numbers, so first or last returns cannot be told",
                     Remedy::return_filter);
  }
  const std::size_t before = out.size();
  try {
    if (path == "-") return read_stream(STDIN_FILENO, name, sel, out, threads);
    // Pipes and devices (e.g. /dev/stdin, <(command)) cannot be mapped: stream them.
    struct stat st {};
    if (::stat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode) && !S_ISDIR(st.st_mode)) {
      const detail::FileHandle file(path);
      return read_stream(file.fd(), path, sel, out, threads);
    }
    return read_mapped(path, sel, out, threads);
  } catch (const std::bad_alloc&) {
    const std::size_t read = out.size() - before;
    out.resize(before);  // frees nothing, but allocates nothing either
    throw Error(name, "", "out of memory after reading " + count_text(read) + " of its points");
  }
}

}  // namespace tincdt::io
