// A stage of a job: a name, whether the options ask for it, and what it does to the Job.
// The stages and their order are one table, in stages.cpp; each stage is one file
// (stage_<name>.cpp) that defines its Stage object with the options it reads (OptionSpec).
// Adding a stage is a new file, a row in the table and its fields in BuildOptions.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "pipeline/job.hpp"
#include "pipeline/option_spec.hpp"

namespace tincdt::pipeline {

// The files a stage will read or write, declared before anything runs, so that a missing input
// folder, an existing output or an output that is also an input stops the job at once.
struct FilePlan {
  struct File {
    std::string path;
    std::string what;  // for messages: "the stats file (--stats)"
  };
  std::vector<File> inputs;   // as given: "FILE" or "FILE:LAYER", "-" for standard input
  std::vector<File> outputs;  // each written through Job::outputs
  // A folder an output fills with files of its own (the web terrain's): no input and no other
  // output may lie inside it (the outputs whose `what` is the folder's are its own), and CHECK
  // refuses what it holds already.
  struct Folder {
    std::string path;
    std::string what;
    void (*check)(const std::string& path, bool overwrite) = nullptr;
  };
  std::vector<Folder> folders;
};

// What a progress display shows of a stage: what it does, for a person, and what it counts (its
// rate); PHASES: the library calls that report under the stage, in order.
struct StageProgress {
  std::string_view title;  // "" for the stage's name
  std::string_view unit = {};
  std::uint64_t (*items)(const Job& job) = nullptr;
  std::span<const std::string_view> phases = {};
};

// The counts a stage's progress can show as its rate, taken as the stage starts.
namespace stage_items {
std::uint64_t point_file_bytes(const Job& job);  // the sizes of the point files
std::uint64_t points(const Job& job);
std::uint64_t segments(const Job& job);  // constraint segments
std::uint64_t triangles(const Job& job);
}  // namespace stage_items

struct Stage {
  // Progress name, the key of the per-stage report entries, and the name the test hooks use.
  std::string_view name;
  // The timings_s key the stage's time adds to (BuildReport::Timings::add); "" for none.
  std::string_view timing;
  bool (*wanted)(const BuildOptions& options);
  void (*run)(Job& job);
  // The files the stage reads or writes (may be null: none).
  void (*plan)(const BuildOptions& options, FilePlan& files) = nullptr;
  // What the stage does, for the help's list of the stages in order ('\n' breaks the line);
  // "" for a stage that is part of the one before it.
  std::string_view title = {};
  // The options the stage reads, declared beside its work.
  std::span<const OptionSpec> options = {};
  // How a progress display names the stage and what it counts.
  StageProgress progress = {};
};

// The stages of a build, in order (stages.cpp).
std::span<const Stage* const> stages();

// Runs every wanted stage of LIST in order on JOB: the progress callback sees each stage's name
// at 0 when it starts and at 1 when it ends, and each adds its time to the report.
void run_stages(Job& job, std::span<const Stage* const> list);

// The files the wanted stages of LIST will read and write.
FilePlan plan_files(const BuildOptions& options, std::span<const Stage* const> list);

// A whole job on LIST: the checks on FILES (plan_files() of LIST, and any file the caller adds),
// the stages (run_stages), then every output moved into place; returns the report. build() is
// this on stages(); a caller with stages of its own runs its own list.
BuildReport run_job(Job& job, std::span<const Stage* const> list, const FilePlan& files);

}  // namespace tincdt::pipeline
