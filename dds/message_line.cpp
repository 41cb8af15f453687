#include "dds/message_line.hpp"

#include <cmath>
#include <cstdio>

namespace headingd::app {

MessageLine::MessageLine(std::string_view topic, bool json) : json_(json) {
  if (json_) {
    out_ = "{\"topic\":\"";
    out_ += topic;
    out_ += '"';
  } else {
    out_ = topic;
  }
}

void MessageLine::key(std::string_view name) {
  if (json_) {
    out_ += ",\"";
    out_ += name;
    out_ += "\":";
  } else {
    out_ += ' ';
    out_ += name;
    out_ += '=';
  }
}

void MessageLine::put_number(double value, const char* format, int digits) {
  if (json_ && !std::isfinite(value)) {
    out_ += "null";
    return;
  }
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, format, digits, value);
  out_ += buffer;
}

MessageLine& MessageLine::number(std::string_view name, double value, int significant_digits) {
  key(name);
  put_number(value, "%.*g", significant_digits);
  return *this;
}

MessageLine& MessageLine::fixed(std::string_view name, double value, int decimals) {
  key(name);
  put_number(value, "%.*f", decimals);
  return *this;
}

MessageLine& MessageLine::count(std::string_view name, std::uint64_t value) {
  key(name);
  out_ += std::to_string(value);
  return *this;
}

MessageLine& MessageLine::numbers(std::string_view name, std::initializer_list<double> values, int significant_digits) {
  key(name);
  out_ += json_ ? '[' : '(';
  bool first = true;
  for (const double v : values) {
    if (!first) out_ += json_ ? ',' : ' ';
    first = false;
    put_number(v, "%.*g", significant_digits);
  }
  out_ += json_ ? ']' : ')';
  return *this;
}

MessageLine& MessageLine::text(std::string_view name, std::string_view value) {
  key(name);
  if (!json_) {
    out_ += value;
    return *this;
  }
  out_ += '"';
  for (const char c : value) {  // escape what JSON requires; our strings are short and plain
    if (c == '"' || c == '\\') {
      out_ += '\\';
      out_ += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char escaped[8];
      std::snprintf(escaped, sizeof escaped, "\\u%04x", static_cast<unsigned>(static_cast<unsigned char>(c)));
      out_ += escaped;
    } else {
      out_ += c;
    }
  }
  out_ += '"';
  return *this;
}

MessageLine& MessageLine::flag(std::string_view name, bool value) {
  key(name);
  out_ += json_ ? (value ? "true" : "false") : (value ? "1" : "0");
  return *this;
}

std::string MessageLine::str() const { return json_ ? out_ + "}" : out_; }

}  // namespace headingd::app
