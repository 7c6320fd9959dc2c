// Logging through spdlog. One logger ("holo") for the whole program, to stderr; under systemd
// (JOURNAL_STREAM set) lines carry syslog priority prefixes ("<4>") so journald keeps levels.
#pragma once

#include <spdlog/spdlog.h>

namespace holo {

enum class LogLevel { Trace, Debug, Info, Warn, Error, Off };

void initLogging(LogLevel level = LogLevel::Info);
LogLevel parseLogLevel(const std::string& name);  // throws InputError on an unknown name
spdlog::logger& logger();

}  // namespace holo

#define HOLO_LOG_DEBUG(...) ::holo::logger().debug(__VA_ARGS__)
#define HOLO_LOG_INFO(...) ::holo::logger().info(__VA_ARGS__)
#define HOLO_LOG_WARN(...) ::holo::logger().warn(__VA_ARGS__)
#define HOLO_LOG_ERROR(...) ::holo::logger().error(__VA_ARGS__)
