#pragma once
#include <cstdint>
#include <stdexcept>
#include <string>

namespace headingd::drivers {

// Bad input that a person must fix: names the file, the line (0 when not line-bound) and
// the problem, formatted as "file:line: problem" like a compiler.
class InputError : public std::runtime_error {
 public:
  InputError(std::string file, std::uint64_t line, std::string problem)
      : std::runtime_error(format(file, line, problem)),
        file_(std::move(file)),
        line_(line),
        problem_(std::move(problem)) {}

  const std::string& file() const { return file_; }
  std::uint64_t line() const { return line_; }
  const std::string& problem() const { return problem_; }

 private:
  static std::string format(const std::string& file, std::uint64_t line, const std::string& problem) {
    return line > 0 ? file + ":" + std::to_string(line) + ": " + problem : file + ": " + problem;
  }
  std::string file_;
  std::uint64_t line_;
  std::string problem_;
};

// The input could not be opened or read at all (missing file, permission, I/O error).
class OpenError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace headingd::drivers
