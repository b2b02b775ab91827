// One file written at once inside a folder that is itself a temporary output (OutputSet::
// add_folder()): no temporary of its own, flushed to disk before the folder moves into place.
#pragma once

#include <string>
#include <string_view>

namespace tincdt::io {

// Writes BYTES to the new file PATH, making its missing parent folders, and flushes it to disk.
// Throws OutputError naming PATH when it cannot.
void write_whole_file(const std::string& path, std::string_view bytes);

}  // namespace tincdt::io
