// stderr for the command line: log lines and the progress share it.
//
// Progress comes in two forms. On a terminal, one line for the whole run, redrawn in place:
//   [3/6] triangulating [########------------]  42%  1.2M points/s  0:07 elapsed  0:09 left
// (the stage's number, what it does, its bar and percent, its rate, the run's time so far and
// the stage's time left). Elsewhere (a pipe, a batch log), GDAL's form, one line per stage:
//   tincdt: [3/6] triangulating 0...10...20...30...40...50...60...70...80...90...100 - done.
// A stage's line starts once it has made progress or has run for a second, so that an error at
// once stays the only line. Percentages never go back within a stage.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <string>
#include <string_view>
#include <thread>

#include "core/progress.hpp"

namespace tincdt::cli {

enum class ProgressForm { none, line, log };

class Terminal final : public StageWatcher {
 public:
  static Terminal& get() {
    static Terminal t;
    return t;
  }
  ~Terminal() override;

  // From now on progress in FORM (none: no progress); the run's clock starts here.
  void start_progress(ProgressForm form);
  // Stops the progress: erases the line, or ends a stage's unfinished log line.
  void end_progress();

  // Writes one complete line, the progress line out of its way (it comes back at the next
  // report).
  void line(std::string_view text);

  // StageWatcher: the display. report() always says go on; stopping is the caller's.
  void stage_started(const StageStart& stage) override;
  bool report(std::string_view stage, double fraction) override;

 private:
  Terminal() = default;
  using Clock = std::chrono::steady_clock;

  void draw_line_locked(Clock::time_point now);
  void write_ticks_locked(int upto);
  void erase_locked();
  void tick_every_second();

  std::mutex mutex_;
  ProgressForm form_ = ProgressForm::none;
  Clock::time_point run_started_{};
  // The running stage, as announced.
  std::string name_, title_, unit_;
  int number_ = 0, count_ = 0;
  std::uint64_t items_ = 0;
  Clock::time_point stage_started_{};
  double fraction_ = 0;  // the largest heard in the stage
  bool in_stage_ = false;
  // Line form: what is on screen.
  bool shown_ = false;
  Clock::time_point drawn_{};
  int percent_drawn_ = -1;
  // Log form: GDAL's ticks (0 to 40, each 2.5%) written of the stage's line, and whether that
  // line is open (written, not yet ended).
  int ticks_ = 0;
  bool log_open_ = false;
  // Redraws the line (its clock) or starts a stage's log line while a stage reports nothing.
  std::thread ticker_;
  std::condition_variable wake_;
  bool stop_ticker_ = false;
};

// spdlog's default logger: "tincdt: warning: ..." lines on stderr through the Terminal; info
// lines carry no level word.
void setup_logging();

}  // namespace tincdt::cli
