#include "tools/gnuplot.hpp"

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "io/atomic_file.hpp"
#include "io/csv_out.hpp"

namespace headingd::app {

std::optional<std::string> draw_with_gnuplot(const std::vector<PlotFile>& data, const std::string& script,
                                             const char* picture, const std::string& output) {
  std::string pattern = (std::filesystem::temp_directory_path() / "headingd-plot-XXXXXX").string();
  if (::mkdtemp(pattern.data()) == nullptr) return std::string("cannot make a private temporary directory");
  const std::filesystem::path work = pattern;
  struct Cleanup {
    std::filesystem::path dir;
    ~Cleanup() {
      std::error_code ignored;
      std::filesystem::remove_all(dir, ignored);
    }
  } cleanup{work};
  for (const auto& file : data) {
    const int fd = ::open((work / file.name).c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0600);
    std::FILE* f = fd >= 0 ? ::fdopen(fd, "w") : nullptr;
    if (f == nullptr) return std::string("cannot write the plot data");
    const bool written = std::fwrite(file.text.data(), 1, file.text.size(), f) == file.text.size();
    if (std::fclose(f) != 0 || !written) return std::string("cannot write the plot data");
  }
  int pipe_fds[2];
  if (::pipe2(pipe_fds, O_CLOEXEC) != 0) return std::string("cannot start gnuplot");
  const pid_t child = ::fork();
  if (child < 0) return std::string("cannot start gnuplot");
  if (child == 0) {  // gnuplot reads the script on stdin, in the private directory
    if (::chdir(work.c_str()) != 0 || ::dup2(pipe_fds[0], STDIN_FILENO) < 0) ::_exit(126);
    ::execlp("gnuplot", "gnuplot", static_cast<char*>(nullptr));
    ::_exit(127);
  }
  ::close(pipe_fds[0]);
  std::signal(SIGPIPE, SIG_IGN);  // gnuplot may stop reading early: an error, not a death
  std::size_t sent = 0;
  while (sent < script.size()) {
    const ssize_t n = ::write(pipe_fds[1], script.data() + sent, script.size() - sent);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    sent += static_cast<std::size_t>(n);
  }
  ::close(pipe_fds[1]);
  int status = 0;
  while (::waitpid(child, &status, 0) < 0 && errno == EINTR) {
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
    return std::string(WIFEXITED(status) && WEXITSTATUS(status) == 127
                           ? "gnuplot is not installed (apt-get install gnuplot-nox)"
                           : "gnuplot failed");
  std::ifstream in(work / picture, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (bytes.empty()) return std::string("gnuplot drew nothing");
  try {
    write_file_atomically(output, bytes);
  } catch (const OutputError& error) {
    return std::string(error.what());
  }
  return std::nullopt;
}

}  // namespace headingd::app
