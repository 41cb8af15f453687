#include "service/log.hpp"

#include <chrono>
#include <cstdio>
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

}  // namespace

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
      std::fprintf(stderr, "<%d>headingd: %d more like \"%s\" held back\n", static_cast<int>(priority), w.held_back,
                   key.c_str());
    w = Window{now, 0, 0};
  }
  if (w.printed >= kBurst) {
    ++w.held_back;
    return;
  }
  ++w.printed;
  std::fprintf(stderr, "<%d>headingd: %s\n", static_cast<int>(priority), message.c_str());
}

}  // namespace headingd::app
