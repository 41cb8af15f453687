#include "service/standard_output.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "service/exit_codes.hpp"

namespace headingd::app {

int finish_standard_output() {
  errno = 0;
  const bool failed = std::fflush(stdout) != 0 || std::ferror(stdout) != 0;
  if (!failed) return kExitOk;
  const int error = errno;
  if (error == EPIPE) return kExitOk;
  std::fprintf(stderr, "headingd: cannot write to standard output: %s\n",
               error != 0 ? std::strerror(error) : "write error");
  return kExitCantCreate;
}

}  // namespace headingd::app
