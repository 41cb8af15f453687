#pragma once
#include <cstdint>
#include <initializer_list>
#include <string>
#include <string_view>

namespace headingd::app {

// One received message as one line, either `topic key=value key=(a b c)` for people or a JSON
// object for programs. Non-finite numbers print as `nan`/`inf` in text and as null in JSON
// (JSON has no NaN), so a NaN variance never makes the line unparsable.
class MessageLine {
 public:
  MessageLine(std::string_view topic, bool json);

  MessageLine& number(std::string_view key, double value, int significant_digits = 9);
  MessageLine& fixed(std::string_view key, double value, int decimals);
  MessageLine& count(std::string_view key, std::uint64_t value);
  MessageLine& numbers(std::string_view key, std::initializer_list<double> values, int significant_digits = 9);
  MessageLine& text(std::string_view key, std::string_view value);
  MessageLine& flag(std::string_view key, bool value);

  std::string str() const;

 private:
  void key(std::string_view name);
  void put_number(double value, const char* format, int digits);

  bool json_;
  std::string out_;
};

}  // namespace headingd::app
