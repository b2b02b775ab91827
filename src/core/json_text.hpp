// JSON string literals (RFC 8259), one escaper for every JSON tincdt writes: build reports, tile
// plans, GeoJSON and the constraint and diagnostics files.
#pragma once

#include <string>
#include <string_view>

namespace tincdt {

// What becomes of bytes that are not valid UTF-8 (possible in file names).
enum class NonUtf8 {
  keep,     // written as they are: a file name read back is the same bytes
  replace,  // each becomes U+FFFD: the text is valid UTF-8 for any JSON reader
};

// TEXT as a JSON string literal, quotes included: '"' and '\' escaped, control characters as
// \b \f \n \r \t or \u00XX.
std::string json_string(std::string_view text, NonUtf8 non_utf8 = NonUtf8::keep);

}  // namespace tincdt
