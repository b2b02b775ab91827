#include "terminal.hpp"

#include <spdlog/sinks/base_sink.h>
#include <spdlog/spdlog.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

#include "core/number_text.hpp"

namespace tincdt::cli {
namespace {

constexpr int kTicks = 40;  // GDAL's: one every 2.5%, a number every 10%
constexpr int kBarWidth = 20;

void write(std::string_view text) {
  std::fwrite(text.data(), 1, text.size(), stderr);
}

double seconds(std::chrono::steady_clock::duration d) {
  return std::chrono::duration<double>(d).count();
}

// "0:07", "12:34", "1:02:03".
std::string clock_text(double s) {
  const auto total = static_cast<long long>(s);
  char text[32];
  if (total >= 3600)
    std::snprintf(text, sizeof text, "%lld:%02lld:%02lld", total / 3600, total / 60 % 60,
                  total % 60);
  else
    std::snprintf(text, sizeof text, "%lld:%02lld", total / 60, total % 60);
  return text;
}

// "850 points/s", "1.2k points/s", "3.4M points/s"; bytes as "45.1 MB/s".
std::string rate_text(double per_second, std::string_view unit) {
  char text[64];
  if (unit == "bytes")
    std::snprintf(text, sizeof text, "%.1f MB/s", per_second / 1e6);
  else if (per_second >= 1e6)
    std::snprintf(text, sizeof text, "%.1fM %.*s/s", per_second / 1e6,
                  static_cast<int>(unit.size()), unit.data());
  else if (per_second >= 1e3)
    std::snprintf(text, sizeof text, "%.1fk %.*s/s", per_second / 1e3,
                  static_cast<int>(unit.size()), unit.data());
  else
    std::snprintf(text, sizeof text, "%.0f %.*s/s", per_second, static_cast<int>(unit.size()),
                  unit.data());
  return text;
}

int terminal_columns() {
  winsize size{};
  if (::ioctl(STDERR_FILENO, TIOCGWINSZ, &size) == 0 && size.ws_col >= 20) return size.ws_col;
  return 80;
}

// GDAL's tick I (0 to 40): the tens as numbers, dots between.
std::string tick_text(int i) {
  return i % 4 == 0 ? std::to_string(i / 4 * 10) : ".";
}

}  // namespace

Terminal::~Terminal() {
  end_progress();
}

void Terminal::start_progress(ProgressForm form) {
  std::lock_guard lock(mutex_);
  form_ = form;
  run_started_ = Clock::now();
  in_stage_ = false;
  if (form_ != ProgressForm::none && !ticker_.joinable()) {
    stop_ticker_ = false;
    ticker_ = std::thread([this] { tick_every_second(); });
  }
}

void Terminal::end_progress() {
  {
    std::lock_guard lock(mutex_);
    erase_locked();
    in_stage_ = false;
    form_ = ProgressForm::none;
    stop_ticker_ = true;
  }
  wake_.notify_all();
  if (ticker_.joinable()) ticker_.join();
  std::fflush(stderr);
}

void Terminal::line(std::string_view text) {
  std::lock_guard lock(mutex_);
  erase_locked();
  write(text);
  std::fputc('\n', stderr);
  if (form_ == ProgressForm::line && in_stage_) draw_line_locked(Clock::now());
  std::fflush(stderr);
}

void Terminal::stage_started(const StageStart& stage) {
  std::lock_guard lock(mutex_);
  if (log_open_) {  // the stage before stopped short of 100
    std::fputc('\n', stderr);
    log_open_ = false;
  }
  name_.assign(stage.name);
  title_.assign(stage.title);
  unit_.assign(stage.unit);
  number_ = stage.number;
  count_ = stage.count;
  items_ = stage.items;
  stage_started_ = Clock::now();
  fraction_ = 0;
  ticks_ = 0;
  in_stage_ = true;
  if (form_ == ProgressForm::line) draw_line_locked(stage_started_);
  std::fflush(stderr);
}

bool Terminal::report(std::string_view stage, double fraction) {
  std::lock_guard lock(mutex_);
  if (form_ == ProgressForm::none || !in_stage_ || stage != name_) return true;
  fraction_ = std::max(fraction_, std::clamp(fraction, 0.0, 1.0));
  if (form_ == ProgressForm::line) {
    const Clock::time_point now = Clock::now();
    const int percent = static_cast<int>(fraction_ * 100.0);
    const auto since = now - drawn_;
    if ((percent != percent_drawn_ && since >= std::chrono::milliseconds(100)) ||
        (percent == 100 && percent_drawn_ != 100) || since >= std::chrono::seconds(1))
      draw_line_locked(now);
  } else {
    const int tick = static_cast<int>(fraction_ * kTicks + 1e-9);
    if (tick >= 1 && tick >= ticks_) write_ticks_locked(tick);
  }
  std::fflush(stderr);
  return true;
}

// "[3/6] triangulating [####----]  42%  1.2M points/s  0:07 elapsed  0:09 left", cut to the
// terminal's width so that it never wraps (a wrapped line cannot be redrawn in place).
void Terminal::draw_line_locked(Clock::time_point now) {
  const int percent = static_cast<int>(fraction_ * 100.0);
  const auto filled = static_cast<std::size_t>(std::lround(fraction_ * kBarWidth));
  std::string text = "[" + count_text(number_) + "/" + count_text(count_) + "] " + title_ + " [" +
                     std::string(filled, '#') +
                     std::string(static_cast<std::size_t>(kBarWidth) - filled, '-') + "] ";
  char pct[8];
  std::snprintf(pct, sizeof pct, "%3d%%", percent);
  text += pct;
  const double stage_s = seconds(now - stage_started_);
  if (items_ > 0 && !unit_.empty() && fraction_ > 0 && stage_s >= 0.5)
    text += "  " + rate_text(static_cast<double>(items_) * fraction_ / stage_s, unit_);
  text += "  " + clock_text(seconds(now - run_started_)) + " elapsed";
  if (fraction_ >= 0.01 && fraction_ < 1 && stage_s >= 1)
    text += "  " + clock_text(stage_s * (1 - fraction_) / fraction_) + " left";
  const auto width = static_cast<std::size_t>(terminal_columns() - 1);
  if (text.size() > width) text.resize(width);
  write("\r\x1b[K");
  write(text);
  shown_ = true;
  drawn_ = now;
  percent_drawn_ = percent;
}

// The stage's log line up to tick UPTO: its start when not yet written (or cut by a message),
// then the ticks, then " - done." at 100.
void Terminal::write_ticks_locked(int upto) {
  if (ticks_ > kTicks) return;
  if (!log_open_) {
    write("tincdt: [" + count_text(number_) + "/" + count_text(count_) + "] " + title_ + " ");
    log_open_ = true;
  }
  for (; ticks_ <= upto; ++ticks_) write(tick_text(ticks_));
  if (ticks_ > kTicks) {
    write(" - done.\n");
    log_open_ = false;
  }
}

void Terminal::erase_locked() {
  if (shown_) {
    write("\r\x1b[K");
    shown_ = false;
    percent_drawn_ = -1;
  }
  if (log_open_) {
    std::fputc('\n', stderr);
    log_open_ = false;
  }
}

void Terminal::tick_every_second() {
  std::unique_lock lock(mutex_);
  while (!stop_ticker_) {
    wake_.wait_for(lock, std::chrono::seconds(1));
    if (stop_ticker_ || !in_stage_) continue;
    const Clock::time_point now = Clock::now();
    if (form_ == ProgressForm::line && now - drawn_ >= std::chrono::seconds(1))
      draw_line_locked(now);
    else if (form_ == ProgressForm::log && ticks_ == 0 &&
             now - stage_started_ >= std::chrono::seconds(1))
      write_ticks_locked(0);
    std::fflush(stderr);
  }
}

namespace {

// "tincdt: warning: ..." on stderr; info lines carry no level word.
class StderrSink final : public spdlog::sinks::base_sink<spdlog::details::null_mutex> {
 protected:
  void sink_it_(const spdlog::details::log_msg& msg) override {
    std::string text = "tincdt: ";
    switch (msg.level) {
      case spdlog::level::trace:
      case spdlog::level::debug:
        text += "debug: ";
        break;
      case spdlog::level::warn:
        text += "warning: ";
        break;
      case spdlog::level::err:
      case spdlog::level::critical:
        text += "error: ";
        break;
      default:
        break;
    }
    text.append(msg.payload.data(), msg.payload.size());
    Terminal::get().line(text);
  }
  void flush_() override { std::fflush(stderr); }
};

}  // namespace

void setup_logging() {
  auto logger = std::make_shared<spdlog::logger>("tincdt", std::make_shared<StderrSink>());
  logger->set_level(spdlog::level::info);
  logger->flush_on(spdlog::level::trace);
  spdlog::set_default_logger(std::move(logger));
}

}  // namespace tincdt::cli
