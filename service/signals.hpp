#pragma once
#include <atomic>
// SIGINT and SIGTERM set a flag; the loops act on it (and shut down in order).
namespace headingd::app {
void install_stop_signals();
bool stop_requested();
// SIGHUP: reload the configuration. Returns true once per signal.
bool take_reload_request();
const std::atomic<bool>& stop_flag();
}  // namespace headingd::app
