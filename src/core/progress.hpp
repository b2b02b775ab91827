// Progress reporting for long stages: a callback that may also cancel.
#pragma once

#include <cstdint>
#include <functional>
#include <string_view>

#include "core/error.hpp"

namespace tincdt {

// Called with the stage name ("read", "delaunay", ...) and the fraction done in [0, 1].
// Returning false asks the library to stop; it then throws Cancelled.
using ProgressFn = std::function<bool(std::string_view stage, double fraction)>;

// A stage as a person follows it: its place among the stages that will run, what it does, and
// what it counts (for a rate).
struct StageStart {
  std::string_view name;   // as the ProgressFn's stage
  std::string_view title;  // "triangulating"
  int number = 0;          // 1-based, of COUNT
  int count = 0;
  std::string_view unit;    // what ITEMS counts ("points", "bytes"), "" when nothing
  std::uint64_t items = 0;  // over the whole stage
};

// A progress display: hears each stage start besides the fractions. Given to the library as a
// ProgressFn (watching()), so that every call that takes a ProgressFn takes it; whoever runs the
// stages finds it there (watcher_of()) and tells it of each stage.
class StageWatcher {
 public:
  virtual ~StageWatcher() = default;
  virtual void stage_started(const StageStart& stage) = 0;
  // As a ProgressFn: false asks the library to stop.
  virtual bool report(std::string_view stage, double fraction) = 0;
};

struct StageWatcherCall {
  StageWatcher* watcher;
  bool operator()(std::string_view stage, double fraction) const {
    return watcher->report(stage, fraction);
  }
};

inline ProgressFn watching(StageWatcher& watcher) {
  return StageWatcherCall{&watcher};
}

// The watcher FN wraps, or null when FN is an ordinary callback (or null).
inline StageWatcher* watcher_of(const ProgressFn* fn) {
  const StageWatcherCall* call = fn ? fn->target<StageWatcherCall>() : nullptr;
  return call ? call->watcher : nullptr;
}

// Rate-limited wrapper used inside hot loops: tick(i) costs one compare unless a report is due.
class Progress {
 public:
  Progress() = default;
  Progress(const ProgressFn* fn, std::string_view stage, std::uint64_t total)
      : fn_(fn && *fn ? fn : nullptr), stage_(stage), total_(total ? total : 1) {
    step_ = total_ / 200 + 1;
    next_ = fn_ ? 0 : UINT64_MAX;
  }

  void tick(std::uint64_t done) {
    if (done >= next_) report(done);
  }
  void finish() {
    if (fn_) report(total_);
  }
  // For the inner steps of one item, which may be many: every 2^16th call reports the last
  // fraction again, so that a request to stop still gets through.
  void heartbeat() {
    if (fn_ && (++beats_ & 0xffff) == 0) report(done_);
  }

 private:
  void report(std::uint64_t done) {
    done_ = done;
    next_ = done + step_;
    if (!(*fn_)(stage_, static_cast<double>(done) / static_cast<double>(total_))) throw Cancelled();
  }

  const ProgressFn* fn_ = nullptr;
  std::string_view stage_;
  std::uint64_t total_ = 1;
  std::uint64_t step_ = UINT64_MAX;
  std::uint64_t next_ = UINT64_MAX;
  std::uint64_t done_ = 0;   // at the last report
  std::uint64_t beats_ = 0;  // heartbeat() calls
};

}  // namespace tincdt
