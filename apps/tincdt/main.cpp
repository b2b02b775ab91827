// tincdt: the command line over pipeline::build (tiles::build_tile for a tile of a plan).
// Options -> BuildOptions and TileOptions (cli_options.cpp),
// spdlog on stderr, tincdt::Error -> one-line message and exit code (0 ok, 1 error, 2 usage,
// 3 internal error), Ctrl-C -> the job stops, leaves every file as it was and ends by the signal.
// Standard output carries only what was asked for there: the help, the version, --stats -.
#include <signal.h>
#include <unistd.h>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <new>
#include <string>
#include <string_view>
#include <vector>

#include "cli_options.hpp"
#include "command_words.hpp"
#include "core/error.hpp"
#include "error_message.hpp"
#include "io/mesh/tin_writer.hpp"
#include "pipeline/build.hpp"
#include "pipeline/stage.hpp"
#include "summary.hpp"
#include "terminal.hpp"
#include "tile_commands.hpp"
#include "tiles/tile_job.hpp"

#ifndef TINCDT_VERSION
#error "TINCDT_VERSION must be defined by the build (the CMake project version)"
#endif

namespace {

using namespace tincdt;

constexpr int kExitOk = 0;
constexpr int kExitFailure = 1;
constexpr int kExitUsage = 2;
constexpr int kExitInternal = 3;

// ---- interruption ----------------------------------------------------------------------------
// The first SIGINT / SIGTERM / SIGHUP stops the job at its next progress report; the stack
// unwinds and removes every temporary file. A second one ends the process at once, after
// removing the temporaries itself, unless the outputs are being moved into place (a few renames
// with these signals blocked): then it lets them finish.

volatile std::sig_atomic_t g_signal = 0;

extern "C" void on_signal(int sig) {
  if (g_signal == 0) {
    g_signal = sig;
    return;
  }
  if (!pipeline::remove_temporaries_for_exit()) return;
  ::signal(sig, SIG_DFL);
  ::raise(sig);
}

void install_signal_handlers() {
  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) sigaction(sig, &sa, nullptr);
}

// For the tests of interruption: TINCDT_TEST_SIGNAL=STAGE:SIGNAL[:COUNT] raises SIGNAL (INT,
// TERM or HUP) COUNT times (default 1) when the stage STAGE ("read", ..., "commit") starts, as
// a user's Ctrl-C would arrive there.
struct SignalHook {
  std::string stage;
  int signal = 0;
  int count = 1;

  static SignalHook from_environment() {
    SignalHook hook;
    const char* spec = std::getenv("TINCDT_TEST_SIGNAL");
    if (spec == nullptr) return hook;
    const std::string s(spec);
    const std::size_t a = s.find(':');
    if (a == std::string::npos) return hook;
    const std::size_t b = s.find(':', a + 1);
    const std::string name = s.substr(a + 1, b == std::string::npos ? b : b - a - 1);
    hook.signal = name == "INT" ? SIGINT : name == "TERM" ? SIGTERM : name == "HUP" ? SIGHUP : 0;
    if (b != std::string::npos) hook.count = std::max(1, std::atoi(s.c_str() + b + 1));
    hook.stage = s.substr(0, a);
    return hook;
  }
  void at(std::string_view running, double fraction) {
    if (signal == 0 || fraction != 0.0 || running != stage) return;
    for (int i = 0; i < count; ++i) ::raise(signal);
    signal = 0;
  }
};

// ---- running ---------------------------------------------------------------------------------

// The help's first paragraph; the mesh formats from the one format table.
std::string description() {
  std::string titles;
  for (const io::TinFormatInfo& f : io::tin_formats())
    titles += (titles.empty() ? "" : ", ") + std::string(f.title);
  return "tincdt " TINCDT_VERSION
         ": exact constrained Delaunay TIN from LiDAR (LAS, LAZ) and XYZ points with breaklines, "
         "as a mesh (" +
         titles + "), a DEM and contour lines.";
}

int usage_error(const std::string& message) {
  spdlog::error(message);
  cli::Terminal::get().line("Try 'tincdt --help' for more information.");
  return kExitUsage;
}

void log_line(int level, const std::string& message) {
  switch (level) {
    case pipeline::log_debug:
      spdlog::debug(message);
      break;
    case pipeline::log_info:
      spdlog::info(message);
      break;
    default:
      spdlog::warn(message);
      break;
  }
}

// --stats -: the JSON document on standard output, once every file is in place.
int print_stats(const pipeline::BuildReport& report) {
  std::string json = report.to_json();
  if (json.empty() || json.back() != '\n') json += '\n';
  if (std::fwrite(json.data(), 1, json.size(), stdout) != json.size() || std::fflush(stdout) != 0) {
    spdlog::error("cannot write the stats to standard output");
    return kExitFailure;
  }
  return kExitOk;
}

// "-" names standard input among the inputs; as an output it would be a file named "-". Every
// output is a temporary moved into place with the others at the end, which a stream cannot be,
// so only --stats (printed once the files are in place) takes "-".
std::string standard_output_refused(const pipeline::BuildOptions& options,
                                    const tiles::TileOptions& tiling) {
  const std::string why =
      " cannot be standard output ('-'): tincdt writes every output to a temporary file and "
      "moves them into place together at the end; give a file name (only --stats takes '-')";
  for (const pipeline::FilePlan::File& output :
       pipeline::plan_files(options, pipeline::stages()).outputs)
    if (output.path == "-") return output.what + why;
  if (tiling.outline == "-") return "the tile's outline (--outline)" + why;
  return {};
}

// tincdt alone: what it does and how to call it, as GDAL's tools answer no arguments.
int no_arguments() {
  std::string usage = description() + "\n" + cli::usage();
  usage.pop_back();
  cli::Terminal::get().line(usage);
  return usage_error("no input and no output: give INPUT... (or --contours LINES) and -o OUTPUT");
}

// The run's progress: each report is where a signal stops the job, and the terminal shows it.
class RunProgress final : public StageWatcher {
 public:
  RunProgress() : hook_(SignalHook::from_environment()) {}
  void stage_started(const StageStart& stage) override {
    stage_now_ = stage.name;
    cli::Terminal::get().stage_started(stage);
  }
  bool report(std::string_view stage, double fraction) override {
    hook_.at(stage, fraction);
    if (g_signal != 0) return false;
    return cli::Terminal::get().report(stage, fraction);
  }
  // The stage last started, for "out of memory".
  const std::string& stage_now() const { return stage_now_; }

 private:
  SignalHook hook_;
  std::string stage_now_ = "read";
};

// On a terminal the redrawn line, elsewhere GDAL's per-stage lines; none with -q unless
// --progress.
cli::ProgressForm progress_form(const cli::Verbosity& verbosity) {
  if (verbosity.quiet && !verbosity.progress) return cli::ProgressForm::none;
  return ::isatty(STDERR_FILENO) == 1 ? cli::ProgressForm::line : cli::ProgressForm::log;
}

// Runs the job, a tile of a plan when TILING names one; the exit code.
int build(const pipeline::BuildOptions& options, const tiles::TileOptions& tiling,
          const cli::Verbosity& verbosity) {
  cli::Terminal::get().start_progress(progress_form(verbosity));
  RunProgress watcher;
  const ProgressFn progress = watching(watcher);
  if (std::find(options.inputs.begin(), options.inputs.end(), "-") != options.inputs.end() &&
      ::isatty(STDIN_FILENO) == 1)
    spdlog::info("reading x y z lines from the terminal; end with Ctrl-D");
  install_signal_handlers();
  try {
    const pipeline::BuildReport report =
        tiling.plan.empty() ? pipeline::build(options, &progress, log_line)
                            : tiles::build_tile(tiling, options, &progress, log_line);
    cli::Terminal::get().end_progress();
    cli::log_summary(options, report);
    return options.stats_path == "-" ? print_stats(report) : kExitOk;
  } catch (const Cancelled& e) {
    cli::Terminal::get().end_progress();
    if (g_signal == 0) {
      spdlog::error(e.what());
      return kExitFailure;
    }
    // Temporaries are gone (the stack has unwound); die of the signal so that the shell and
    // scripts see an interrupted command, not an ordinary failure.
    spdlog::error("interrupted; no file was changed");
    const int sig = g_signal;
    ::signal(sig, SIG_DFL);
    ::raise(sig);
    return kExitFailure;
  } catch (const std::bad_alloc&) {
    cli::Terminal::get().end_progress();
    spdlog::error("out of memory in the " + watcher.stage_now() + " stage");
    return kExitFailure;
  }
}

int run(int argc, char** argv) {
  cli::setup_logging();
  if (argc > 1 && std::string_view(argv[1]) == "plan") return cli::run_plan(argc - 1, argv + 1);
  if (argc > 1 && std::string_view(argv[1]) == "merge") return cli::run_merge(argc - 1, argv + 1);
  CLI::App app(description(), "tincdt");
  pipeline::BuildOptions options;
  tiles::TileOptions tiling;
  cli::Verbosity verbosity;
  cli::define_options(app, options, tiling, verbosity);
  if (argc <= 1) return no_arguments();
  const std::vector<std::string> words = cli::with_gdal_words(argc, argv);
  if (const auto unknown = cli::unknown_long_option(app, words)) return usage_error(*unknown);
  try {
    cli::parse_words(app, words);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    return usage_error(e.what());
  }
  if (verbosity.quiet && verbosity.verbose)
    return usage_error("-q/--quiet and -v/--verbose exclude each other");
  if (verbosity.quiet) spdlog::set_level(spdlog::level::warn);
  if (verbosity.verbose) spdlog::set_level(spdlog::level::debug);
  if (const std::string refused = standard_output_refused(options, tiling); !refused.empty())
    return usage_error(refused);
  try {
    tiles::check_options(tiling, options);  // build() checks again; this tells usage from failure
  } catch (const UsageError& e) {
    return usage_error(cli::error_message(e));
  }
  return build(options, tiling, verbosity);
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const InternalError& e) {
    cli::Terminal::get().end_progress();
    spdlog::error(e.what());
    return kExitInternal;
  } catch (const UsageError& e) {
    cli::Terminal::get().end_progress();
    return usage_error(cli::error_message(e));
  } catch (const Error& e) {
    cli::Terminal::get().end_progress();
    spdlog::error(cli::error_message(e));
    return kExitFailure;
  } catch (const std::bad_alloc&) {
    cli::Terminal::get().end_progress();
    spdlog::error("out of memory");
    return kExitFailure;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "tincdt: error: %s\n", e.what());
    return kExitFailure;
  } catch (...) {
    std::fprintf(stderr, "tincdt: error: unknown failure\n");
    return kExitFailure;
  }
}
