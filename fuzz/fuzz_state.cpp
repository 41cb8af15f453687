// libFuzzer target: the state file parser on arbitrary bytes. Any input ends in a StateError or
// a state that passes the estimator's own check, restores without throwing, and leaves the
// estimator's output finite (the oracle of issue 15: nothing absurd gets in through a restart).
// A mutated file almost never keeps a valid checksum, so three inputs in four (by their size)
// are resealed first: without it the fields behind the checksum were hardly ever reached.
#include <cmath>
#include <string>

#include "core/estimator.hpp"
#include "io/state_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const unsigned char* data, std::size_t size) {
  std::string text(reinterpret_cast<const char*>(data), size);
  if (size % 4 != 0) text = headingd::app::seal_state(text.substr(0, text.rfind("checksum=")));
  headingd::app::SavedState state;
  try {
    state = headingd::app::parse_state(text, "fuzz.state");
  } catch (const headingd::app::StateError&) {
    return 0;
  }
  if (headingd::core::implausible(state)) __builtin_trap();  // the parser let through what restore refuses
  headingd::core::Estimator estimator;
  estimator.restore(state);  // must not throw: it passed the same check
  headingd::core::Sample sample;
  for (int i = 0; i < 2000; ++i) {
    sample.t_s = i / 400.0;
    sample.rate_dps = headingd::core::Vec3(0.1, -0.2, 0.3);
    sample.temp_c = 20.0 + i * 0.001;
    const auto& e = estimator.update(sample);
    if (!std::isfinite(e.heading_deg) || std::isnan(e.heading_sigma_deg) || !e.attitude.coeffs().allFinite() ||
        !e.bias_dps.allFinite())
      __builtin_trap();
    if (!std::isfinite(e.heading_sigma_deg) && !e.fault) __builtin_trap();
  }
  // What would be saved again is as sane as what was read.
  if (headingd::core::implausible(estimator.learned())) __builtin_trap();
  return 0;
}
