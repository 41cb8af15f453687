#include "core/method.hpp"

namespace headingd::core {

std::string_view method_name(Method method) {
  switch (method) {
    case Method::A:
      return "a";
    case Method::B:
      return "b";
    case Method::C:
      return "c";
    case Method::Auto:
      return "auto";
  }
  return "?";
}

std::optional<Method> parse_method(std::string_view text) {
  if (text == "auto" || text == "AUTO" || text == "Auto") return Method::Auto;
  if (text.size() != 1) return std::nullopt;
  switch (text[0]) {
    case 'a':
    case 'A':
      return Method::A;
    case 'b':
    case 'B':
      return Method::B;
    case 'c':
    case 'C':
      return Method::C;
    default:
      return std::nullopt;
  }
}

}  // namespace headingd::core
