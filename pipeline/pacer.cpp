#include "pipeline/pacer.hpp"

#include <cmath>
#include <cstdlib>
#include <thread>

namespace headingd::pipeline {
namespace {
// A gap in a recording can be hours long: sleep in short steps so a signal is seen at once.
constexpr auto kLongestSleep = std::chrono::milliseconds(50);
}  // namespace

Pacer::Pacer(double factor, const std::atomic<bool>* stop) : factor_(factor), stop_(stop) {}

bool Pacer::wait(const core::Sample& sample) {
  if (!started_) {
    started_ = true;
    first_t_s_ = sample.t_s;
    start_ = std::chrono::steady_clock::now();
  }
  const auto due = start_ + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                std::chrono::duration<double>((sample.t_s - first_t_s_) / factor_));
  while (true) {
    if (stop_ != nullptr && stop_->load()) return false;
    const auto now = std::chrono::steady_clock::now();
    if (now >= due) return true;
    std::this_thread::sleep_for(std::min<std::chrono::steady_clock::duration>(due - now, kLongestSleep));
  }
}

std::optional<double> parse_speed(const std::string& text) {
  if (text == "max") return 0.0;
  if (text == "realtime") return 1.0;
  char* end = nullptr;
  const double factor = std::strtod(text.c_str(), &end);
  if (end == text.c_str() || *end != '\0' || !(factor > 0.0) || !std::isfinite(factor)) return std::nullopt;
  return factor;
}

}  // namespace headingd::pipeline
