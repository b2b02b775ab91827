// The further files a GDAL driver writes beside the one it was given (a shapefile's .shx and
// .dbf, an ASCII grid's .prj, a PAM .aux.xml): found by name beside the writer's file and moved
// into place as outputs of their own, so they appear with it or not at all.
#pragma once

#include <dirent.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "core/error.hpp"
#include "io/output_file.hpp"

namespace tincdt::io {

// The output for a further file of the dataset, at PATH ("lines.dbf" beside "lines.shp"): a
// new output of the caller's OutputSet. Throws OutputError as OutputSet::add().
using SiblingOutput = std::function<OutputFile&(const std::string& path)>;

// The files GDAL made beside the one at MAIN ("x.tmp.shx" beside "x.tmp.shp"), removed when
// the object goes unless moved into place: a failed write leaves none of them.
class SiblingFiles {
 public:
  explicit SiblingFiles(const std::string& main) : main_(main) {
    const auto slash = main.rfind('/');
    folder_ = slash == std::string::npos ? "." : main.substr(0, slash);
    const std::string name = main.substr(slash == std::string::npos ? 0 : slash + 1);
    stem_ = name.substr(0, name.rfind('.') + 1);  // "x.tmp."
  }
  SiblingFiles(const SiblingFiles&) = delete;
  SiblingFiles& operator=(const SiblingFiles&) = delete;
  ~SiblingFiles() {
    for (const std::string& f : list()) (void)::unlink(f.c_str());
  }

  // Their paths, sorted.
  std::vector<std::string> list() const {
    std::vector<std::string> files;
    if (stem_.empty()) return files;
    DIR* d = ::opendir(folder_.c_str());
    if (d == nullptr) return files;
    while (const dirent* entry = ::readdir(d)) {
      const std::string path = folder_ + "/" + entry->d_name;
      if (path != main_ && std::string_view(entry->d_name).substr(0, stem_.size()) == stem_)
        files.push_back(path);
    }
    (void)::closedir(d);
    std::sort(files.begin(), files.end());
    return files;
  }

  // Where FILE (one of list()) goes beside TARGET, the main file's place: the part of its name
  // after the main file's stem replaces TARGET's extension ("x.tmp.prj" -> "dem.prj",
  // "x.tmp.asc.aux.xml" -> "dem.asc.aux.xml").
  std::string target_of(const std::string& file, const std::string& target) const {
    const std::string suffix = file.substr(file.rfind('/') + 1 + stem_.size());  // after "x.tmp."
    return std::filesystem::path(target).replace_extension().string() + "." + suffix;
  }

  // Moves every file into the output SIBLING gives for it beside TARGET (closed, not committed);
  // their bytes. Throws OutputError when there are some and no SIBLING (DRIVER names the format).
  std::uint64_t move_into_place(const std::string& target, const SiblingOutput& sibling,
                                const std::string& driver) const {
    std::uint64_t bytes = 0;
    for (const std::string& file : list()) {
      if (!sibling) throw OutputError(target, "", "the " + driver + " format writes several files");
      const std::string place = target_of(file, target);
      OutputFile& other = sibling(place);
      if (std::rename(file.c_str(), other.take_path().c_str()) != 0) {
        const int err = errno;
        throw OutputError(
            place, "",
            "cannot move the new file into place: " + std::generic_category().message(err));
      }
      other.close();
      bytes += other.bytes_written();
    }
    return bytes;
  }

 private:
  std::string main_;
  std::string folder_;
  std::string stem_;
};

}  // namespace tincdt::io
