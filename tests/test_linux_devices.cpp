// The Linux I2C and GPIO back ends open real device paths. This machine has neither
// /dev/i2c-* nor /dev/gpiochip*, which is exactly what the error paths need.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstring>
#include <fstream>
#include <functional>

#include "hw/gpiod_data_ready.hpp"
#include "hw/linux_i2c_bus.hpp"
#include "temp_dir.hpp"

using namespace headingd::drivers;
using headingd::test::TempDir;

namespace {

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& error) {
    return error.what();
  }
  return "(no error)";
}

// Runs f as an unprivileged user (root would bypass file permissions) and returns its error.
std::string error_as_nobody(const std::function<void()>& f) {
  if (::geteuid() != 0) return error_of(f);
  int pipe_fds[2];
  if (::pipe(pipe_fds) != 0) return "pipe failed";
  const pid_t child = ::fork();
  if (child == 0) {
    ::close(pipe_fds[0]);
    if (::setgid(65534) != 0 || ::setuid(65534) != 0) _exit(2);
    const std::string message = error_of(f);
    if (::write(pipe_fds[1], message.data(), message.size()) < 0) _exit(3);
    _exit(0);
  }
  ::close(pipe_fds[1]);
  std::string message;
  char buffer[512];
  ssize_t n;
  while ((n = ::read(pipe_fds[0], buffer, sizeof buffer)) > 0) message.append(buffer, static_cast<std::size_t>(n));
  ::close(pipe_fds[0]);
  int status = 0;
  ::waitpid(child, &status, 0);
  return message;
}

}  // namespace

TEST(LinuxI2cBus, MissingAdapterNamesPathAndFix) {
  const auto message = error_of([] { LinuxI2cBus bus("/dev/i2c-7"); });
  EXPECT_NE(message.find("cannot open I2C adapter /dev/i2c-7: No such file or directory"), std::string::npos)
      << message;
  EXPECT_NE(message.find("i2c-dev"), std::string::npos) << message;
}

TEST(LinuxI2cBus, PermissionDeniedNamesTheGroup) {
  TempDir dir;
  const auto path = dir.file("i2c-1", "");
  ::chmod(path.c_str(), 0600);
  ::chmod(dir.path("").c_str(), 0755);
  const auto message = error_as_nobody([&] { LinuxI2cBus bus(path); });
  EXPECT_NE(message.find("Permission denied"), std::string::npos) << message;
  EXPECT_NE(message.find("group 'i2c'"), std::string::npos) << message;
}

TEST(LinuxI2cBus, NotAnAdapterIsSaid) {
  const auto message = error_of([] { LinuxI2cBus bus("/dev/null"); });
  EXPECT_NE(message.find("/dev/null is not an I2C adapter"), std::string::npos) << message;
}

TEST(GpiodDataReady, MissingChipNamesPathAndFix) {
  GpioLineSettings settings;
  settings.chip = "gpiochip9";
  settings.offset = 17;
  const auto message = error_of([&] { GpiodDataReady line(settings); });
  EXPECT_NE(message.find("cannot open GPIO chip /dev/gpiochip9"), std::string::npos) << message;
}

TEST(GpiodDataReady, PermissionDeniedNamesTheGroup) {
  TempDir dir;
  const auto path = dir.file("gpiochip0", "");
  ::chmod(path.c_str(), 0600);
  ::chmod(dir.path("").c_str(), 0755);
  GpioLineSettings settings;
  settings.chip = path;
  const auto message = error_as_nobody([&] { GpiodDataReady line(settings); });
  EXPECT_NE(message.find("Permission denied"), std::string::npos) << message;
  EXPECT_NE(message.find("group 'gpio'"), std::string::npos) << message;
}

TEST(PollDataReady, WaitsAndReportsNoEdges) {
  PollDataReady poll(std::chrono::milliseconds(2));
  const auto before = poll.now_ns();
  EXPECT_FALSE(poll.wait(std::chrono::milliseconds(50)).has_value());
  EXPECT_GE(poll.now_ns() - before, 2'000'000);
  EXPECT_FALSE(poll.has_edges());
}
