#include "holo/core/log.hpp"

#include <spdlog/pattern_formatter.h>
#include <spdlog/sinks/ringbuffer_sink.h>
#include <spdlog/sinks/stdout_sinks.h>
#include <algorithm>
#include <cstdlib>

#include "holo/core/error.hpp"
#include "holo/core/log_tail.hpp"

namespace holo {

namespace {
// "%*" expands to the syslog priority of the message, which journald reads from "<N>" at the
// start of each line of a stream it captures (sd-daemon(3)).
class SyslogPriorityFlag : public spdlog::custom_flag_formatter {
 public:
  void format(const spdlog::details::log_msg& msg, const std::tm&, spdlog::memory_buf_t& dest) override {
    static constexpr char priorities[] = {'7', '7', '6', '4', '3', '2', '6'};
    dest.push_back(priorities[static_cast<int>(msg.level)]);
  }
  std::unique_ptr<custom_flag_formatter> clone() const override {
    return std::make_unique<SyslogPriorityFlag>();
  }
};

std::shared_ptr<spdlog::sinks::ringbuffer_sink_mt> tailSink() {
  static const auto sink = [] {
    auto s = std::make_shared<spdlog::sinks::ringbuffer_sink_mt>(kLogTailLines);
    s->set_formatter(std::make_unique<spdlog::pattern_formatter>("%Y-%m-%d %H:%M:%S.%e %l %v",
                                                                 spdlog::pattern_time_type::utc, ""));
    return s;
  }();
  return sink;
}

std::shared_ptr<spdlog::logger> makeLogger() {
  auto stderr_sink = std::make_shared<spdlog::sinks::stderr_sink_mt>();
  auto formatter = std::make_unique<spdlog::pattern_formatter>();
  if (std::getenv("JOURNAL_STREAM") != nullptr)
    formatter->add_flag<SyslogPriorityFlag>('*').set_pattern("<%*>%v");
  else
    formatter->set_pattern("[%H:%M:%S.%e] [%^%l%$] %v");
  stderr_sink->set_formatter(std::move(formatter));
  return std::make_shared<spdlog::logger>("holo", spdlog::sinks_init_list{stderr_sink, tailSink()});
}
}  // namespace

spdlog::logger& logger() {
  static std::shared_ptr<spdlog::logger> instance = makeLogger();
  return *instance;
}

std::vector<std::string> logTail(std::size_t max_lines) {
  if (max_lines == 0) return {};  // spdlog reads 0 as "all"
  return tailSink()->last_formatted(std::min(max_lines, kLogTailLines));
}

void initLogging(LogLevel level) {
  static constexpr spdlog::level::level_enum levels[] = {spdlog::level::trace, spdlog::level::debug,
                                                         spdlog::level::info,  spdlog::level::warn,
                                                         spdlog::level::err,   spdlog::level::off};
  logger().set_level(levels[static_cast<int>(level)]);
}

LogLevel parseLogLevel(const std::string& name) {
  if (name == "trace") return LogLevel::Trace;
  if (name == "debug") return LogLevel::Debug;
  if (name == "info") return LogLevel::Info;
  if (name == "warn") return LogLevel::Warn;
  if (name == "error") return LogLevel::Error;
  if (name == "off") return LogLevel::Off;
  throw InputError("", "--log-level", "one of trace, debug, info, warn, error, off", name);
}

}  // namespace holo
