#include "io/output_set.hpp"

#include <fcntl.h>
#include <pthread.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <filesystem>
#include <random>
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

// How to take back one folder moved into place.
enum class FolderUndo {
  move_back,             // the target did not exist: move it back to the temporary's name
  move_back_make_empty,  // the target was an empty folder: move back, make the empty folder again
  exchange,              // the old folder now sits at the temporary's name: exchange them back
};

bool folder_is_empty(const std::string& path) {
  std::error_code ec;
  return std::filesystem::is_empty(path, ec) && !ec;
}

FolderUndo move_folder_into_place(const std::string& from, const std::string& to, bool overwrite) {
  const bool was_empty = ::rmdir(to.c_str()) == 0;  // only an empty folder goes
  const FolderUndo moved = was_empty ? FolderUndo::move_back_make_empty : FolderUndo::move_back;
  if (::renameat2(AT_FDCWD, from.c_str(), AT_FDCWD, to.c_str(), RENAME_NOREPLACE) == 0)
    return moved;
  int err = errno;
  if (err == EINVAL || err == ENOSYS) {  // no renameat2: rename() replaces only an empty folder
    struct stat st {};
    if (::lstat(to.c_str(), &st) != 0 && std::rename(from.c_str(), to.c_str()) == 0) return moved;
    err = ::lstat(to.c_str(), &st) == 0 ? EEXIST : errno;
  }
  if (was_empty) (void)::mkdir(to.c_str(), 0777);
  if (err != EEXIST) throw OutputError(to, "", "cannot create the folder: " + error_text(err));
  if (!overwrite) throw OutputError(to, "", "already exists", Remedy::overwrite);
  if (::renameat2(AT_FDCWD, from.c_str(), AT_FDCWD, to.c_str(), RENAME_EXCHANGE) == 0)
    return FolderUndo::exchange;
  err = errno;
  throw OutputError(to, "", "cannot replace the folder: " + error_text(err));
}

void take_back_folder(const std::string& from, const std::string& to, FolderUndo undo) noexcept {
  if (undo == FolderUndo::exchange) {
    (void)::renameat2(AT_FDCWD, from.c_str(), AT_FDCWD, to.c_str(), RENAME_EXCHANGE);
    return;
  }
  (void)std::rename(to.c_str(), from.c_str());
  if (undo == FolderUndo::move_back_make_empty) (void)::mkdir(to.c_str(), 0777);
}

// fsync of FOLDER and every folder in it, so that the files' names in them are durable.
void sync_tree(const std::string& folder) {
  std::error_code ec;
  detail::sync_folder_of(folder + "/.");
  for (std::filesystem::recursive_directory_iterator it(folder, ec), end; !ec && it != end;
       it.increment(ec))
    if (it->is_directory(ec)) detail::sync_folder_of(it->path().string() + "/.");
}

// A name for a new folder beside PATH: "<dir>/.<name>.tmp-XXXXXX".
std::string make_temporary_folder(const std::string& path) {
  std::string target = path;
  while (target.size() > 1 && target.back() == '/') target.pop_back();
  const auto slash = target.rfind('/');
  const std::string dir = slash == std::string::npos ? "." : target.substr(0, slash + 1);
  const std::string name = slash == std::string::npos ? target : target.substr(slash + 1);
  static constexpr char kLetters[] =
      "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789";
  std::random_device random;
  for (int attempt = 0; attempt < 100; ++attempt) {
    std::string temp = (slash == std::string::npos ? "" : dir) + "." + name + ".tmp-";
    for (int i = 0; i < 6; ++i) temp += kLetters[random() % (sizeof kLetters - 1)];
    if (::mkdir(temp.c_str(), 0777) == 0) return temp;  // the umask applies, as to any folder
    if (errno != EEXIST) {
      const int err = errno;
      throw OutputError(path, "", "cannot create a folder in '" + dir + "': " + error_text(err));
    }
  }
  throw OutputError(path, "", "cannot find a free temporary name in '" + dir + "'");
}

}  // namespace

OutputSet::~OutputSet() {
  entries_.clear();
  if (committed_) return;
  remove_folder_temporaries();
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

const std::string& OutputSet::add_folder(const std::string& path, const std::string& replaceable) {
  if (committed_) throw OutputError(path, "", "the outputs were committed already");
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0) {
    if (!S_ISDIR(st.st_mode)) throw OutputError(path, "", "is not a folder");
    if (!folder_is_empty(path)) {
      struct stat marker {};
      if (::stat((path + "/" + replaceable).c_str(), &marker) != 0)
        throw OutputError(path, "",
                          "is a folder without " + replaceable +
                              ", which is not replaced: give a new or empty folder");
      if (!overwrite_) throw OutputError(path, "", "already exists", Remedy::overwrite);
    }
  }
  Folder folder{path, make_temporary_folder(path)};
  folder.temp_slot = detail::track_temporary(folder.temp_path, true);
  folders_.push_back(std::move(folder));
  return folders_.back().temp_path;
}

void OutputSet::remove_folder_temporaries() noexcept {
  for (Folder& f : folders_) {
    std::error_code ec;
    std::filesystem::remove_all(f.temp_path, ec);
    detail::untrack_temporary(f.temp_slot);
  }
  folders_.clear();
}

const OutputSet::Entry* OutputSet::entry_of(const OutputFile& file) const {
  const auto it = by_file_.find(&file);
  return it == by_file_.end() ? nullptr : &entries_[it->second];
}

void OutputSet::commit(const std::function<bool()>& proceed) {
  if (committed_) return;
  for (Entry& e : entries_) e.file->close();
  for (const Folder& f : folders_) sync_tree(f.temp_path);
  std::vector<Undo> moved;
  moved.reserve(entries_.size());
  std::vector<FolderUndo> folders_moved;
  {
    const TerminationBlock block;
    const auto remove_temporaries = [this] {  // while no signal can end the process
      entries_.clear();
      remove_folder_temporaries();
    };
    bool go = false;
    try {
      go = (!proceed || proceed()) && !block.pending();  // a signal PROCEED saw is pending
    } catch (...) {
      remove_temporaries();
      throw;
    }
    if (!go) {
      remove_temporaries();
      throw Cancelled();
    }
    try {
      for (Entry& e : entries_)
        moved.push_back(move_into_place(e.file->temp_path(), e.file->path(), overwrite_));
      for (const Folder& f : folders_)
        folders_moved.push_back(move_folder_into_place(f.temp_path, f.path, overwrite_));
    } catch (...) {
      for (std::size_t i = folders_moved.size(); i-- > 0;)
        take_back_folder(folders_[i].temp_path, folders_[i].path, folders_moved[i]);
      for (std::size_t i = moved.size(); i-- > 0;)
        take_back(entries_[i].file->temp_path(), entries_[i].file->path(), moved[i]);
      remove_temporaries();
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
  // The folders replaced, now at the temporaries' names, go (a second Ctrl-C meanwhile removes
  // the rest: they are still tracked).
  for (std::size_t i = 0; i < folders_.size(); ++i) {
    Folder& f = folders_[i];
    std::error_code ec;
    if (folders_moved[i] == FolderUndo::exchange) std::filesystem::remove_all(f.temp_path, ec);
    detail::untrack_temporary(f.temp_slot);
    detail::sync_folder_of(f.path);
  }
  committed_ = true;
}

}  // namespace tincdt::io
