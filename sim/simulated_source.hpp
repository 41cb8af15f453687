#pragma once
// The gyro simulator as a sample source, for benchmarks and tests that drive the pipeline
// with a known truth: each read also keeps the truth of the samples it returned.
#include <string>
#include <vector>

#include "core/sample_source.hpp"
#include "sim/gyro_simulator.hpp"

namespace headingd::drivers {

class SimulatedSource final : public core::SampleSource {
 public:
  SimulatedSource(const Scenario& scenario, std::uint64_t seed);
  std::size_t read(std::span<core::Sample> out) override;
  void close() override { closed_ = true; }
  std::string describe() const override;
  core::SourceHealth health() const override;
  double nominal_rate_hz() const override { return simulator_.scenario().noise.rate_hz; }
  // The truth of the samples the last read returned, in the same order.
  const std::vector<TruthPoint>& truth() const { return truth_; }

 private:
  GyroSimulator simulator_;
  std::uint64_t seed_;
  std::vector<TruthPoint> truth_;
  std::uint64_t samples_ = 0;
  bool closed_ = false;
};

}  // namespace headingd::drivers
