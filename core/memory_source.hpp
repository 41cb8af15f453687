#pragma once
// Samples already in memory as a source: benchmarks time the pipeline without the cost of
// reading or simulating, and tests feed it exact sequences.
#include <algorithm>
#include <span>
#include <string>

#include "core/sample_source.hpp"

namespace headingd::core {

class MemorySource final : public SampleSource {
 public:
  explicit MemorySource(std::span<const Sample> samples) : samples_(samples) {}
  std::size_t read(std::span<Sample> out) override {
    const std::span<const Sample> view = next(out);
    std::copy(view.begin(), view.end(), out.begin());
    return view.size();
  }
  std::span<const Sample> next(std::span<Sample> scratch) override {
    const std::span<const Sample> view = samples_.subspan(next_, std::min(scratch.size(), samples_.size() - next_));
    next_ += view.size();
    return view;
  }
  void close() override { next_ = samples_.size(); }
  std::string describe() const override { return std::to_string(samples_.size()) + " samples in memory"; }
  SourceHealth health() const override {
    SourceHealth health;
    health.samples = next_;
    return health;
  }

 private:
  std::span<const Sample> samples_;
  std::size_t next_ = 0;
};

}  // namespace headingd::core
