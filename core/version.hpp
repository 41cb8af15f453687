#pragma once
namespace headingd::app {
inline constexpr const char* kVersion = "0.1.0";
}  // namespace headingd::app
