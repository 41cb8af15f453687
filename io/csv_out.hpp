#pragma once
// Buffered CSV writer: numbers formatted with to_chars into a large buffer, written in
// big blocks. "-" writes to standard output. Write errors throw OutputError naming the file.
#include <cstdint>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace headingd::app {

class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The reader of a pipe went away (`headingd replay ... | head -1`): not a fault of ours, and
// nothing more to write; the run ends quietly.
class OutputClosed : public OutputError {
 public:
  using OutputError::OutputError;
};

class CsvOut {
 public:
  explicit CsvOut(std::string path);
  ~CsvOut();
  CsvOut(const CsvOut&) = delete;
  CsvOut& operator=(const CsvOut&) = delete;

  CsvOut& text(std::string_view value);
  CsvOut& number(double value, int decimals);  // fixed notation; NaN written as "nan"
  CsvOut& exact(double value);                 // the shortest fixed text that reads back as the same double
  CsvOut& integer(std::int64_t value);
  void end_line();
  void line(std::string_view whole_line);  // a complete line, e.g. a header or comment
  void flush();
  void push();   // flush, and hand the bytes to the system (a crash after it loses none of them)
  void close();  // flushes; throws if anything could not be written
  const std::string& path() const { return path_; }

 private:
  void separator();
  void reserve(std::size_t bytes);

  std::string path_;
  std::FILE* file_ = nullptr;
  bool owns_file_ = false;
  std::vector<char> buffer_;
  std::size_t used_ = 0;
  bool line_started_ = false;
};

}  // namespace headingd::app
