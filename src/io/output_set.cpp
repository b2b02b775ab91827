#include "io/output_set.hpp"

#include <fcntl.h>
#include <pthread.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <filesystem>
#include <set>
#include <system_error>
#include <utility>

#include "core/error.hpp"
#include "io/temporary_registry.hpp"

namespace tincdt::io {
namespace {

std::string error_text(int err) {
  return std::generic_category().message(err);
}

// The usual ways to end a process from outside, held back on this thread while the files move,
// so that a Ctrl-C lands before the first rename or after the last, never in between.
class TerminationBlock {
 public:
  TerminationBlock() {
    sigemptyset(&set_);
    for (int sig : kSignals) sigaddset(&set_, sig);
    pthread_sigmask(SIG_BLOCK, &set_, &old_);
    detail::set_committing(true);
  }
  ~TerminationBlock() {
    detail::set_committing(false);
    pthread_sigmask(SIG_SETMASK, &old_, nullptr);
  }
  TerminationBlock(const TerminationBlock&) = delete;
  TerminationBlock& operator=(const TerminationBlock&) = delete;

  bool pending() const {
    sigset_t pending;
    if (sigpending(&pending) != 0) return false;
    for (int sig : kSignals)
      if (sigismember(&pending, sig) == 1) return true;
    return false;
  }

 private:
  static constexpr int kSignals[] = {SIGINT, SIGTERM, SIGHUP};
  sigset_t set_{};
  sigset_t old_{};
};

// Flushes the file systems that hold the temporaries of ENTRIES whose fsync was deferred: one
// syncfs(2) a file system. Throws OutputError naming the first such file when one fails.
void sync_deferred(const std::vector<OutputSet::Entry>& entries) {
  std::set<dev_t> synced;
  for (const OutputSet::Entry& e : entries) {
    if (!e.file->sync_deferred()) continue;
    struct stat st {};
    if (::stat(e.file->temp_path().c_str(), &st) != 0 || !synced.insert(st.st_dev).second)
      continue;  // a temporary that is gone fails its rename, which says so
    const int fd = ::open(e.file->temp_path().c_str(), O_RDONLY | O_CLOEXEC);
    const bool ok = fd >= 0 && ::syncfs(fd) == 0;
    const int err = errno;
    if (fd >= 0) (void)::close(fd);
    if (!ok) throw OutputError(e.file->path(), "", "cannot flush to disk: " + error_text(err));
  }
}

// How to take back one file moved into place.
enum class Undo {
  remove,    // the target did not exist: remove it again
  exchange,  // the old target now sits at the temporary's name: exchange them back
  none,      // the file system could not exchange: the old content is gone
};

Undo move_into_place(const std::string& from, const std::string& to, bool overwrite) {
  int err = detail::move_without_replacing(from, to);
  if (err == 0) return Undo::remove;
  if (err != EEXIST) throw OutputError(to, "", "cannot create the file: " + error_text(err));
  if (!overwrite) throw OutputError(to, "", "already exists", Remedy::overwrite);
  struct stat st {};
  if (::lstat(to.c_str(), &st) == 0 && !S_ISREG(st.st_mode) && !S_ISLNK(st.st_mode))
    throw OutputError(to, "", "is not a regular file and cannot be replaced");
  if (::renameat2(AT_FDCWD, from.c_str(), AT_FDCWD, to.c_str(), RENAME_EXCHANGE) == 0)
    return Undo::exchange;
  err = errno;
  if (err != EINVAL && err != ENOSYS)
    throw OutputError(to, "", "cannot replace the file: " + error_text(err));
  if (std::rename(from.c_str(), to.c_str()) != 0) {
    err = errno;
    throw OutputError(to, "", "cannot replace the file: " + error_text(err));
  }
  return Undo::none;
}

void take_back(const std::string& from, const std::string& to, Undo undo) noexcept {
  switch (undo) {
    case Undo::remove:
      (void)::unlink(to.c_str());
      break;
    case Undo::exchange:
      (void)::renameat2(AT_FDCWD, from.c_str(), AT_FDCWD, to.c_str(), RENAME_EXCHANGE);
      break;
    case Undo::none:
      break;
  }
}

}  // namespace

OutputSet::~OutputSet() {
  entries_.clear();
  if (committed_) return;
  std::error_code ec;
  for (auto it = made_folders_.rbegin(); it != made_folders_.rend(); ++it)
    std::filesystem::remove(*it, ec);  // only an empty folder goes
}

void OutputSet::make_folders(const std::string& folder) {
  std::vector<std::filesystem::path> missing;
  std::error_code ec;
  for (std::filesystem::path p = folder; !p.empty() && !std::filesystem::exists(p, ec);
       p = p.parent_path())
    missing.push_back(p);
  for (auto it = missing.rbegin(); it != missing.rend(); ++it) {
    if (!std::filesystem::create_directory(*it, ec) && ec)
      throw OutputError(it->string(), "", "cannot create the folder: " + ec.message());
    made_folders_.push_back(it->string());
  }
}

OutputFile& OutputSet::add(const std::string& path, std::string kind) {
  if (committed_) throw OutputError(path, "", "the outputs were committed already");
  if (const auto it = by_path_.find(path); it != by_path_.end())
    throw OutputError(path, "",
                      "is both the " + entries_[it->second].kind + " and the " + kind + " output");
  auto file = std::make_unique<OutputFile>(path, overwrite_);
  by_path_.emplace(path, entries_.size());
  by_file_.emplace(file.get(), entries_.size());
  entries_.push_back({std::move(kind), std::move(file)});
  return *entries_.back().file;
}

const OutputSet::Entry* OutputSet::entry_of(const OutputFile& file) const {
  const auto it = by_file_.find(&file);
  return it == by_file_.end() ? nullptr : &entries_[it->second];
}

void OutputSet::commit(const std::function<bool()>& proceed) {
  if (committed_) return;
  for (Entry& e : entries_) e.file->close();
  try {
    sync_deferred(entries_);
  } catch (...) {
    entries_.clear();  // removes the temporaries
    throw;
  }
  std::vector<Undo> moved;
  moved.reserve(entries_.size());
  {
    const TerminationBlock block;
    bool go = false;
    try {
      go = (!proceed || proceed()) && !block.pending();  // a signal PROCEED saw is pending
    } catch (...) {
      entries_.clear();  // removes the temporaries while no signal can end the process
      throw;
    }
    if (!go) {
      entries_.clear();
      throw Cancelled();
    }
    try {
      for (Entry& e : entries_)
        moved.push_back(move_into_place(e.file->temp_path(), e.file->path(), overwrite_));
    } catch (...) {
      for (std::size_t i = moved.size(); i-- > 0;)
        take_back(entries_[i].file->temp_path(), entries_[i].file->path(), moved[i]);
      entries_.clear();
      throw;
    }
    // Every file is in place; the old contents left at the temporaries' names go now.
    for (std::size_t i = 0; i < entries_.size(); ++i) {
      OutputFile& f = *entries_[i].file;
      if (moved[i] == Undo::exchange) (void)::unlink(f.temp_path().c_str());
      f.committed_ = true;
      f.forget_temporary();
    }
  }
  std::set<std::string> folders;
  for (const Entry& e : entries_)
    if (folders.insert(e.file->path().substr(0, e.file->path().rfind('/') + 1)).second)
      detail::sync_folder_of(e.file->path());
  committed_ = true;
  for (const std::function<void()>& task : after_commit_) task();
}

}  // namespace tincdt::io
