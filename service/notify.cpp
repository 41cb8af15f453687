#include "service/notify.hpp"

#include <systemd/sd-daemon.h>

#include <cstdint>

namespace headingd::app {

Notifier::Notifier() {
  std::uint64_t usec = 0;
  if (sd_watchdog_enabled(0, &usec) > 0) watchdog_period_ = std::chrono::microseconds(usec / 2);
}

void Notifier::ready() {
  if (ready_sent_) return;
  ready_sent_ = true;
  sd_notify(0, "READY=1");
}

void Notifier::sample_loop_alive() {
  if (!watchdog_enabled()) return;
  const auto now = std::chrono::steady_clock::now();
  if (now - last_ping_ < watchdog_period_) return;
  last_ping_ = now;
  sd_notify(0, "WATCHDOG=1");
}

void Notifier::status(const std::string& text) { sd_notify(0, ("STATUS=" + text).c_str()); }

void Notifier::stopping() { sd_notify(0, "STOPPING=1"); }

}  // namespace headingd::app
