// Private to output_file.cpp and output_set.cpp: renames, and the names of this process's temporary
// output files, kept where a signal handler can read them (fixed slots, no allocation, no lock), so
// that remove_temporaries_for_exit() can delete them when a second Ctrl-C ends the process at once.
#pragma once

#include <string>

namespace tincdt::io::detail {

// Records PATH; returns its slot, or -1 when every slot is taken or the name is too long (the
// file is then only removed by its owner, which is what happens on every ordinary exit).
int track_temporary(const std::string& path) noexcept;
void untrack_temporary(int& slot) noexcept;  // sets slot to -1

// Renames FROM to TO unless TO exists; 0 or the errno (EEXIST when TO exists).
int move_without_replacing(const std::string& from, const std::string& to) noexcept;

// fsync of PATH's folder, so that renames in it are durable; failures are ignored.
void sync_folder_of(const std::string& path) noexcept;

// While set, remove_temporaries_for_exit() leaves the files alone (OutputSet::commit).
void set_committing(bool on) noexcept;

}  // namespace tincdt::io::detail
