// The checks on a job's files that run before any work, so that a long job never fails at its
// end over a file it could have refused at its start, and never writes over an input. Commands
// other than the build run check_files() on their own files too.
#pragma once

#include <string>

#include "pipeline/stage.hpp"

namespace tincdt::pipeline {

// Every planned output writable (as check_output_path), no two of them the same file, and none
// of them (with its sidecars) an input or an input's sidecar, whatever OVERWRITE says; no input
// and no other output inside a planned folder, whose own check passes; standard input read once.
void check_files(const FilePlan& plan, bool overwrite);

}  // namespace tincdt::pipeline

namespace tincdt::pipeline::detail {

// Refuses an output the writers would refuse at the end: a folder, an existing file without
// OVERWRITE, something that is not a regular file, a folder that is missing or not writable.
void check_output_path(const std::string& path, bool overwrite);

// Refuses OUTPUT when it is one of the planned inputs or their sidecars (a shapefile's .prj).
void refuse_input(const FilePlan& plan, const std::string& output, const std::string& what);

// Whether the .prj at PATH describes the CRS WKT (as written, or per OSR).
bool prj_holds(const std::string& path, const std::string& wkt);

}  // namespace tincdt::pipeline::detail
