#pragma once
// One way to report input that cannot be used, for every command that reads a file: a file
// that cannot be opened exits 66 (EX_NOINPUT), a malformed one 65 (EX_DATAERR), each with the
// file (and line) named on stderr.
#include <cstdio>

#include "io/input_error.hpp"
#include "service/exit_codes.hpp"

namespace headingd::app {

// Runs `read`; returns 0, or the exit code for the input error it threw (after printing it).
template <typename Read>
int report_input_errors(Read&& read) {
  try {
    read();
    return kExitOk;
  } catch (const drivers::OpenError& error) {
    std::fprintf(stderr, "headingd: %s\n", error.what());
    return kExitNoInput;
  } catch (const drivers::InputError& error) {
    std::fprintf(stderr, "headingd: %s\n", error.what());
    return kExitDataError;
  }
}

}  // namespace headingd::app
