// Every file a run writes, as one transaction: each output is written to its own temporary file
// beside its target (OutputFile), and commit() moves all of them into place, or none. A failure
// or a cancellation before or during commit() leaves every existing file as it was and no
// temporary file.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "io/output_file.hpp"

namespace tincdt::io {

class OutputSet {
 public:
  struct Entry {
    std::string kind;  // what the file is, for the report: "tin", "prj", "stats", ...
    std::unique_ptr<OutputFile> file;
  };

  // overwrite: targets that exist may be replaced (--overwrite).
  explicit OutputSet(bool overwrite) : overwrite_(overwrite) {}
  OutputSet(const OutputSet&) = delete;
  OutputSet& operator=(const OutputSet&) = delete;
  // Uncommitted: the OutputFiles remove their temporaries, then the folders make_folders()
  // made go, those left empty.
  ~OutputSet();

  // Makes FOLDER and its missing parents, for outputs of the set inside it.
  void make_folders(const std::string& folder);

  // A new output at PATH; its temporary is created now (OutputFile's checks: the target exists
  // without overwrite, the folder is not writable). Throws OutputError when PATH is already an
  // output of the set.
  OutputFile& add(const std::string& path, std::string kind);

  const std::vector<Entry>& entries() const { return entries_; }
  // The entry of FILE, an output of the set (null for another file).
  const Entry* entry_of(const OutputFile& file) const;
  bool overwrite() const { return overwrite_; }

  // Closes every file (flushed to disk). Then, with SIGINT, SIGTERM and SIGHUP blocked on this
  // thread, removes every temporary and throws Cancelled when one of those signals is pending
  // or `proceed` (the caller's last check) returns false; otherwise moves the files into place
  // in the order added. When one cannot be moved, those already moved are put back (a replaced
  // target gets its old content again, a new one is removed) and the OutputError is thrown. An
  // empty set commits nothing.
  void commit(const std::function<bool()>& proceed = {});
  // TASK runs at the end of a successful commit(), once every file is in place, never otherwise
  // (tasks in the order given). It must not throw: the outputs are committed, whatever it meets.
  void after_commit(std::function<void()> task) { after_commit_.push_back(std::move(task)); }
  bool committed() const { return committed_; }

 private:
  std::vector<Entry> entries_;
  // Lookups by path and by file, so that a pyramid's many outputs cost constant time each.
  std::unordered_map<std::string, std::size_t> by_path_;
  std::unordered_map<const OutputFile*, std::size_t> by_file_;
  std::vector<std::string> made_folders_;  // in the order made, parents first
  std::vector<std::function<void()>> after_commit_;
  bool overwrite_;
  bool committed_ = false;
};

}  // namespace tincdt::io
