// systemd's notify protocol against a real Unix datagram socket set as NOTIFY_SOCKET:
// READY after the first sample, WATCHDOG pings while samples flow and none once the
// (simulated) sensor dies, STOPPING on SIGTERM, exit 0.
#include <gtest/gtest.h>
#include <poll.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <string>
#include <vector>

#include "temp_dir.hpp"

using Clock = std::chrono::steady_clock;

namespace {

struct Message {
  double t_s;
  std::string text;
};

}  // namespace

TEST(Notify, ReadyWatchdogStoppingFromTheSampleLoop) {
  headingd::test::TempDir dir;
  const std::string socket_path = dir.path("notify.sock");
  const int fd = ::socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  ASSERT_GE(fd, 0);
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  std::snprintf(address.sun_path, sizeof address.sun_path, "%s", socket_path.c_str());
  ASSERT_EQ(::bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address), 0);

  const auto start = Clock::now();
  const pid_t child = ::fork();
  if (child == 0) {
    ::setenv("NOTIFY_SOCKET", socket_path.c_str(), 1);
    ::setenv("WATCHDOG_USEC", "400000", 1);  // pings every 0.2 s at most
    ::unsetenv("WATCHDOG_PID");
    // The simulated chip runs at its real pace and dies 2 s in.
    ::execl(HEADINGD_BINARY, HEADINGD_BINARY, "run", "--simulated-chip", "still", "--sim-realtime", "--sim-dead-after",
            "2", "--no-dds", static_cast<char*>(nullptr));
    _exit(127);
  }
  std::vector<Message> messages;
  bool terminated = false;
  double term_at = 0.0;
  int status = 0;
  while (true) {
    const double now = std::chrono::duration<double>(Clock::now() - start).count();
    if (!terminated && now > 4.0) {
      ::kill(child, SIGTERM);
      terminated = true;
      term_at = now;
    }
    if (terminated && ::waitpid(child, &status, WNOHANG) == child) break;
    ASSERT_LT(now, 20.0) << "headingd did not exit";
    pollfd p{fd, POLLIN, 0};
    if (::poll(&p, 1, 20) > 0) {
      char buffer[512];
      const auto n = ::recv(fd, buffer, sizeof buffer, 0);
      if (n > 0) {
        std::string text(buffer, static_cast<std::size_t>(n));
        // One datagram may carry several assignments separated by newlines.
        std::size_t from = 0;
        while (from < text.size()) {
          const auto end = text.find('\n', from);
          messages.push_back({std::chrono::duration<double>(Clock::now() - start).count(),
                              text.substr(from, end == std::string::npos ? std::string::npos : end - from)});
          if (end == std::string::npos) break;
          from = end + 1;
        }
      }
    }
  }
  ::close(fd);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0);

  double ready_at = -1, stopping_at = -1;
  int early_pings = 0, late_pings = 0;
  for (const auto& m : messages) {
    if (m.text == "READY=1") ready_at = m.t_s;
    if (m.text == "STOPPING=1") stopping_at = m.t_s;
    if (m.text == "WATCHDOG=1") {
      EXPECT_GE(ready_at, 0.0) << "a ping before READY";
      if (m.t_s < 2.0) ++early_pings;
      if (m.t_s > 2.8 && m.t_s < term_at) ++late_pings;
    }
  }
  EXPECT_GE(ready_at, 0.0) << "no READY=1";
  EXPECT_LT(ready_at, 1.5);
  EXPECT_GE(early_pings, 3) << "pings while samples flow";
  EXPECT_EQ(late_pings, 0) << "pings after the sensor died";
  EXPECT_GE(stopping_at, term_at) << "STOPPING=1 after SIGTERM";
}
