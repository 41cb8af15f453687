#include "sim/simulated_source.hpp"

namespace headingd::drivers {

SimulatedSource::SimulatedSource(const Scenario& scenario, std::uint64_t seed)
    : simulator_(scenario, seed), seed_(seed) {}

std::size_t SimulatedSource::read(std::span<core::Sample> out) {
  truth_.resize(out.size());
  std::size_t count = 0;
  while (!closed_ && count < out.size() && !simulator_.done()) {
    simulator_.step(out[count], truth_[count]);
    ++count;
  }
  truth_.resize(count);
  samples_ += count;
  return count;
}

std::string SimulatedSource::describe() const {
  return "simulated gyro, scenario " + simulator_.scenario().name + ", seed " + std::to_string(seed_);
}

core::SourceHealth SimulatedSource::health() const {
  core::SourceHealth health;
  health.samples = samples_;
  health.rate_hz = simulator_.scenario().noise.rate_hz;
  return health;
}

}  // namespace headingd::drivers
