#pragma once
#include <optional>
#include <string_view>

namespace headingd::core {

// The paper's named baselines (docs/algorithm.md):
//   A: bias measured once at start-up, never changed;
//   B: bias from every segment passing the range criterion;
//   C: bias from segments passing the range and the mean-consistency criteria;
// and headingd's own estimator (auto_estimator.hpp), the default:
//   Auto: Kalman-predicted mean test, short stops, temperature model, zero-rate hold, sigma.
enum class Method { A, B, C, Auto };

std::string_view method_name(Method method);
// Accepts "a", "b", "c", "auto" in either case; nullopt for anything else.
std::optional<Method> parse_method(std::string_view text);

}  // namespace headingd::core
