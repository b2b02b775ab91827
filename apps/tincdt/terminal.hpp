// stderr for the command line: log lines and the progress line share it.
#pragma once

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <mutex>
#include <string>
#include <string_view>

namespace tincdt::cli {

class Terminal {
 public:
  static Terminal& get() {
    static Terminal t;
    return t;
  }

  void enable_progress(bool on) {
    std::lock_guard lock(mutex_);
    progress_on_ = on;
  }

  // Writes one complete line, erasing the progress line first (the next update redraws it).
  void line(std::string_view text) {
    std::lock_guard lock(mutex_);
    erase_locked();
    std::fwrite(text.data(), 1, text.size(), stderr);
    std::fputc('\n', stderr);
    std::fflush(stderr);
  }

  // "tincdt: delaunay 80%", redrawn at most every 100 ms unless the stage changes.
  void progress(std::string_view stage, double fraction) {
    std::lock_guard lock(mutex_);
    if (!progress_on_) return;
    const int percent = static_cast<int>(std::clamp(fraction, 0.0, 1.0) * 100.0);
    const auto now = std::chrono::steady_clock::now();
    const bool new_stage = stage != stage_;
    if (!new_stage &&
        (percent == percent_ || (now - drawn_ < std::chrono::milliseconds(100) && percent != 100)))
      return;
    stage_.assign(stage);
    percent_ = percent;
    drawn_ = now;
    std::fprintf(stderr, "\r\x1b[Ktincdt: %s %d%%", stage_.c_str(), percent);
    std::fflush(stderr);
    shown_ = true;
  }

  void erase_progress() {
    std::lock_guard lock(mutex_);
    erase_locked();
  }

 private:
  void erase_locked() {
    if (!shown_) return;
    std::fputs("\r\x1b[K", stderr);
    shown_ = false;
    stage_.clear();
    percent_ = -1;
  }

  std::mutex mutex_;
  bool progress_on_ = false;
  bool shown_ = false;
  std::string stage_;
  int percent_ = -1;
  std::chrono::steady_clock::time_point drawn_{};
};

// spdlog's default logger: "tincdt: warning: ..." lines on stderr through the Terminal; info
// lines carry no level word.
void setup_logging();

}  // namespace tincdt::cli
