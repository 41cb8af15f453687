#pragma once
// The estimates CSV (`--output`) as a sink.
#include <memory>
#include <string>

#include "io/csv_out.hpp"
#include "io/estimates_writer.hpp"
#include "pipeline/sink.hpp"

namespace headingd::pipeline {

class EstimatesSink final : public Sink {
 public:
  // output_rate_hz 0: every sample. `source_rate_hz` (0: unknown) and the segment length size
  // the writer's wait buffer once. Throws OutputError when the file cannot be created.
  EstimatesSink(const std::string& path, double output_rate_hz, double source_rate_hz, double segment_s);
  void add(const core::Sample& sample, const core::Estimate& estimate, const core::Estimator& estimator) override;
  double next_estimate_due_s() const override { return writer_->next_due_s(); }
  void finish(const core::Estimator& estimator, const core::SampleSource& source) override;
  std::uint64_t rows_written() const { return writer_->rows_written(); }
  const std::string& path() const { return out_.path(); }

 private:
  app::CsvOut out_;
  std::unique_ptr<app::EstimatesWriter> writer_;
};

// Empty when `rate_hz` is usable as --output-rate, else why not.
std::optional<std::string> check_output_rate(double rate_hz);

}  // namespace headingd::pipeline
