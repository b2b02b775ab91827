#include "terminal.hpp"

#include <spdlog/sinks/base_sink.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cstdio>
#include <memory>

namespace tincdt::cli {
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
