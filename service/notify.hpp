#pragma once
// systemd's notify protocol (libsystemd sd_notify): READY=1 after the first good sample,
// WATCHDOG=1 from the sample loop (so a stalled sensor stops the pings and systemd restarts
// us), STATUS= lines, STOPPING=1 on the way out. Without NOTIFY_SOCKET every call is a no-op.
#include <chrono>
#include <string>

namespace headingd::app {

class Notifier {
 public:
  Notifier();
  void ready();
  // Call from the sample loop; pings at half the watchdog interval at most.
  void sample_loop_alive();
  void status(const std::string& text);
  void stopping();
  bool watchdog_enabled() const { return watchdog_period_.count() > 0; }

 private:
  bool ready_sent_ = false;
  std::chrono::microseconds watchdog_period_{0};
  std::chrono::steady_clock::time_point last_ping_{};
};

}  // namespace headingd::app
