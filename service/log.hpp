#pragma once
// Logging to stderr with the priority prefixes journald understands ("<4>" = warning), with a
// level and a rate limit per kind of message, so a fault repeating 400 times a second shows up
// as a few lines and a count rather than a flood.
#include <string>

namespace headingd::app {

enum class LogPriority { Error = 3, Warning = 4, Notice = 5, Info = 6, Debug = 7 };

void set_log_level(LogPriority level);
// "error", "warning", "notice", "info", "debug"; false for anything else.
bool parse_log_level(const std::string& text, LogPriority& level);
// `key` groups repeats: at most 5 lines per key per 10 s, then a count of those held back.
void log(LogPriority priority, const std::string& key, const std::string& message);

}  // namespace headingd::app
