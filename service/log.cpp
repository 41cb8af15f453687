#include "service/log.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <mutex>

namespace headingd::app {
namespace {

constexpr int kBurst = 5;
constexpr std::chrono::seconds kWindow{10};

struct Window {
  std::chrono::steady_clock::time_point start{};
  int printed = 0;
  int held_back = 0;
};

std::mutex g_mutex;
LogPriority g_level = LogPriority::Info;
std::map<std::string, Window> g_windows;

// "<3>" where journald reads it; nothing on a terminal or in a file, where it would be noise.
std::string prefix(LogPriority priority) {
  return stderr_is_journal() ? "<" + std::to_string(static_cast<int>(priority)) + ">" : std::string();
}

}  // namespace

bool stderr_is_journal() {
  static const bool journal = [] {
    const char* stream = std::getenv("JOURNAL_STREAM");  // "device:inode", both decimal
    if (stream == nullptr) return false;
    char* colon = nullptr;
    errno = 0;
    const unsigned long long device = std::strtoull(stream, &colon, 10);
    if (errno != 0 || colon == stream || *colon != ':') return false;
    char* end = nullptr;
    const unsigned long long inode = std::strtoull(colon + 1, &end, 10);
    if (errno != 0 || end == colon + 1 || *end != '\0') return false;
    struct stat status {};
    return fstat(STDERR_FILENO, &status) == 0 && status.st_dev == device && status.st_ino == inode;
  }();
  return journal;
}

void report(LogPriority priority, const std::string& message) {
  std::fprintf(stderr, "%sheadingd: %s\n", prefix(priority).c_str(), message.c_str());
}

void set_log_level(LogPriority level) {
  std::lock_guard lock(g_mutex);
  g_level = level;
}

bool parse_log_level(const std::string& text, LogPriority& level) {
  static const std::map<std::string, LogPriority> names = {{"error", LogPriority::Error},
                                                           {"warning", LogPriority::Warning},
                                                           {"notice", LogPriority::Notice},
                                                           {"info", LogPriority::Info},
                                                           {"debug", LogPriority::Debug}};
  const auto it = names.find(text);
  if (it == names.end()) return false;
  level = it->second;
  return true;
}

void log(LogPriority priority, const std::string& key, const std::string& message) {
  std::lock_guard lock(g_mutex);
  if (static_cast<int>(priority) > static_cast<int>(g_level)) return;
  Window& w = g_windows[key];
  const auto now = std::chrono::steady_clock::now();
  if (now - w.start >= kWindow) {
    if (w.held_back > 0)
      std::fprintf(stderr, "%sheadingd: %d more like \"%s\" held back\n", prefix(priority).c_str(), w.held_back,
                   key.c_str());
    w = Window{now, 0, 0};
  }
  if (w.printed >= kBurst) {
    ++w.held_back;
    return;
  }
  ++w.printed;
  std::fprintf(stderr, "%sheadingd: %s\n", prefix(priority).c_str(), message.c_str());
}

}  // namespace headingd::app
