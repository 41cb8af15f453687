// A stand-in for systemd's end of the notify protocol: binds a Unix datagram socket (the path
// given, as NOTIFY_SOCKET) and appends every assignment it receives to the output file, one per
// line, until SIGTERM. For tests/cli scripts that check READY=1 and STOPPING=1 on a real socket.
// Usage: notify_listener SOCKET_PATH OUTPUT_FILE
#include <poll.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <string>

namespace {
volatile std::sig_atomic_t g_stop = 0;
extern "C" void on_term(int) { g_stop = 1; }
}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: notify_listener SOCKET_PATH OUTPUT_FILE\n");
    return 64;
  }
  const int fd = ::socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  std::snprintf(address.sun_path, sizeof address.sun_path, "%s", argv[1]);
  ::unlink(argv[1]);
  if (fd < 0 || ::bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0) {
    std::perror("notify_listener: bind");
    return 1;
  }
  std::FILE* out = std::fopen(argv[2], "w");
  if (out == nullptr) {
    std::perror("notify_listener: output");
    return 1;
  }
  struct sigaction action {};
  action.sa_handler = on_term;
  sigaction(SIGTERM, &action, nullptr);
  sigaction(SIGINT, &action, nullptr);
  // Drain what is queued even after SIGTERM: the last message may arrive just before it.
  while (true) {
    pollfd p{fd, POLLIN, 0};
    const int ready = ::poll(&p, 1, 50);
    if (ready <= 0) {
      if (g_stop) break;
      continue;
    }
    char buffer[4096];
    const auto n = ::recv(fd, buffer, sizeof buffer, 0);
    if (n <= 0) continue;
    std::string text(buffer, static_cast<std::size_t>(n));
    if (text.back() != '\n') text += '\n';
    std::fputs(text.c_str(), out);
    std::fflush(out);
  }
  std::fclose(out);
  ::unlink(argv[1]);
  return 0;
}
