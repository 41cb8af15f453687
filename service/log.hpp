#pragma once
// Logging to stderr, with a level and a rate limit per kind of message, so a fault repeating 400
// times a second shows up as a few lines and a count rather than a flood. Where stderr is the
// journal's stream (a systemd service), each line carries the priority prefix journald reads
// ("<3>" = err, "<4>" = warning; sd-daemon(3)), so `journalctl -p err` finds what ended a run.
#include <string>

namespace headingd::app {

enum class LogPriority { Error = 3, Warning = 4, Notice = 5, Info = 6, Debug = 7 };

void set_log_level(LogPriority level);
// "error", "warning", "notice", "info", "debug"; false for anything else.
bool parse_log_level(const std::string& text, LogPriority& level);
// `key` groups repeats: at most 5 lines per key per 10 s, then a count of those held back.
void log(LogPriority priority, const std::string& key, const std::string& message);
// One line that is never held back: why a command could not start or why it stopped.
void report(LogPriority priority, const std::string& message);
// Whether stderr is the stream systemd connected to the journal: $JOURNAL_STREAM names its
// device and inode (systemd.exec(5), "Environment variables set or propagated").
bool stderr_is_journal();

}  // namespace headingd::app
