#include "pipeline/file_checks.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "core/error.hpp"
#include "core/quoted_text.hpp"
#include "io/crs.hpp"
#include "io/vector/line_reader.hpp"

namespace tincdt::pipeline::detail {
namespace {

namespace fs = std::filesystem;

// Equal when both name one existing file (device and inode: hard links, symbolic links, "./a"
// and "a"), or, when either does not exist yet, when their canonical paths are equal.
bool same_file(const std::string& a, const std::string& b) {
  struct stat sa {
  }, sb{};
  if (::stat(a.c_str(), &sa) == 0 && ::stat(b.c_str(), &sb) == 0)
    return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
  std::error_code ec;
  const fs::path ca = fs::weakly_canonical(a, ec);
  if (ec) return false;
  const fs::path cb = fs::weakly_canonical(b, ec);
  return !ec && ca == cb;
}

bool upper_case(const std::string& ext) {
  return std::any_of(ext.begin(), ext.end(), [](unsigned char c) { return std::isupper(c); });
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// FILE and the files that belong to it: a shapefile's .shx, .dbf, .prj, ...; an SQLite
// database's (GeoPackage) journals. A vector source may be given as "FILE:LAYER".
std::vector<std::string> with_sidecars(const std::string& spec) {
  const std::string file = io::vector_source_file(spec);
  std::vector<std::string> files = {file};
  const fs::path p(file);
  const std::string ext = p.extension().string();
  const std::string ext_lower = lower(ext);
  static const char* const kShapefile[] = {".shp", ".shx", ".dbf", ".prj",    ".cpg",
                                           ".qix", ".sbn", ".sbx", ".shp.xml"};
  if (std::find_if(std::begin(kShapefile), std::end(kShapefile),
                   [&](const char* e) { return ext_lower == e; }) != std::end(kShapefile)) {
    for (const char* e : kShapefile) {
      std::string sidecar = e;
      if (upper_case(ext))
        for (char& c : sidecar) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
      files.push_back(fs::path(p).replace_extension(sidecar).string());
    }
  } else if (ext_lower == ".gpkg" || ext_lower == ".sqlite" || ext_lower == ".db") {
    for (const char* suffix : {"-journal", "-wal", "-shm"}) files.push_back(file + suffix);
  }
  return files;
}

// PATH's canonical form, through the symbolic links and the "." and ".." of the part that exists,
// without a trailing separator.
fs::path canonical_form(const std::string& path) {
  std::error_code ec;
  fs::path p = fs::weakly_canonical(path, ec);
  if (ec) p = fs::absolute(path, ec).lexically_normal();
  if (!p.empty() && p.filename().empty()) p = p.parent_path();
  return p;
}

// Whether PATH is FOLDER or lies under it (both canonical).
bool inside(const fs::path& folder, const fs::path& path) {
  return std::mismatch(folder.begin(), folder.end(), path.begin(), path.end()).first ==
         folder.end();
}

// Refuses an input or an output (but FOLDER's own) that lies inside FOLDER.
void refuse_inside(const FilePlan& plan, const FilePlan::Folder& folder) {
  const fs::path dir = canonical_form(folder.path);
  const auto refuse = [&](const std::string& file, const std::string& what) {
    if (file == "-" || !inside(dir, canonical_form(file))) return;
    throw UsageError(file, "",
                     what + " lies inside " + folder.what + " " + quoted_text(folder.path) +
                         ", which may hold only that output's files; keep it elsewhere");
  };
  for (const FilePlan::File& input : plan.inputs)
    refuse(io::vector_source_file(input.path), input.what);
  for (const FilePlan::File& output : plan.outputs)
    if (output.what != folder.what) refuse(output.path, output.what);
}

}  // namespace

void check_output_path(const std::string& path, bool overwrite) {
  if (path.empty()) throw OutputError("no output path given");
  std::error_code ec;
  const fs::path target(path);
  const fs::file_status st = fs::status(target, ec);
  if (fs::exists(st)) {
    if (fs::is_directory(st)) throw OutputError(path, "", "is a folder");
    if (!overwrite) throw OutputError(path, "", "already exists", Remedy::overwrite);
    if (!fs::is_regular_file(st))
      throw OutputError(path, "", "is not a regular file and cannot be replaced");
  }
  fs::path folder = target.parent_path();
  if (folder.empty()) folder = ".";
  const fs::file_status fst = fs::status(folder, ec);
  if (!fs::exists(fst))
    throw OutputError(path, "", "folder '" + folder.string() + "' does not exist");
  if (!fs::is_directory(fst))
    throw OutputError(path, "", "'" + folder.string() + "' is not a folder");
  if (::access(folder.c_str(), W_OK | X_OK) != 0) {
    const int err = errno;
    throw OutputError(path, "",
                      "cannot write in folder '" + folder.string() + "': " + std::strerror(err));
  }
}

void refuse_input(const FilePlan& plan, const std::string& output, const std::string& what) {
  for (const FilePlan::File& input : plan.inputs) {
    if (input.path == "-") continue;
    for (const std::string& file : with_sidecars(input.path))
      if (same_file(output, file))
        throw UsageError(output, "",
                         what + " would overwrite " +
                             (file == io::vector_source_file(input.path)
                                  ? std::string("an input, ")
                                  : "'" + file + "', part of the input ") +
                             input.path + " (" + input.what + "); choose another name");
  }
}

bool prj_holds(const std::string& path, const std::string& wkt) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  if (!in && !in.eof()) return false;
  const std::string content = text.str();
  if (content.empty()) return false;
  try {
    return content == io::crs_to_prj(wkt) || io::same_crs(content, wkt);
  } catch (const Error&) {
    return false;
  }
}

}  // namespace tincdt::pipeline::detail

namespace tincdt::pipeline {

void check_files(const FilePlan& plan, bool overwrite) {
  const std::vector<FilePlan::File>& outputs = plan.outputs;
  // An input first: that it exists already is then beside the point.
  for (const FilePlan::File& output : outputs) detail::refuse_input(plan, output.path, output.what);
  for (const FilePlan::Folder& folder : plan.folders) {
    detail::refuse_inside(plan, folder);
    if (folder.check) folder.check(folder.path, overwrite);
  }
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    detail::check_output_path(outputs[i].path, overwrite);
    for (std::size_t j = 0; j < i; ++j)
      if (detail::same_file(outputs[i].path, outputs[j].path))
        throw OutputError(outputs[i].path, "",
                          outputs[i].what + " and " + outputs[j].what + " are the same file");
  }
  if (std::count_if(plan.inputs.begin(), plan.inputs.end(),
                    [](const FilePlan::File& f) { return f.path == "-"; }) > 1)
    throw InputError("-", "", "standard input can be read only once");
}

}  // namespace tincdt::pipeline
