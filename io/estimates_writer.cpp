#include "io/estimates_writer.hpp"

#include <cmath>
#include <limits>

namespace headingd::app {
namespace {
// Output instants are compared with sample times parsed from text; allow their rounding.
constexpr double kTimeEpsilonS = 1e-9;
}  // namespace

EstimatesWriter::EstimatesWriter(CsvOut& out, double output_rate_hz, std::size_t rows_per_segment)
    : out_(out), period_s_(output_rate_hz > 0.0 ? 1.0 / output_rate_hz : 0.0) {
  waiting_.reserve(rows_per_segment + 16);
  out_.line(kEstimatesHeader);
}

bool EstimatesWriter::due(double t_s) {
  if (period_s_ == 0.0) return true;
  if (first_) {
    first_ = false;
    grid_origin_s_ = t_s;
    next_output_s_ = t_s + period_s_;
    return true;
  }
  if (t_s + kTimeEpsilonS < next_output_s_) return false;
  // Stay on the grid started by the first sample; instants lost in a gap are skipped.
  // The grid is origin + k * period (not a running sum, which would drift over hours).
  while (next_output_s_ <= t_s + kTimeEpsilonS) {
    ++grid_step_;
    next_output_s_ = grid_origin_s_ + static_cast<double>(grid_step_ + 1) * period_s_;
  }
  return true;
}

double EstimatesWriter::next_due_s() const {
  if (period_s_ == 0.0 || first_) return -std::numeric_limits<double>::infinity();
  return next_output_s_ - 2.0 * kTimeEpsilonS;  // due() allows one epsilon; a margin beyond it
}

void EstimatesWriter::add(const core::Estimate& estimate) {
  if (estimate.closed.closed) release(estimate.closed.index, estimate.closed.accepted);
  if (!due(estimate.t_s)) return;
  const auto& q = estimate.attitude;
  waiting_.push_back(Row{
      .t_s = estimate.t_s,
      .heading_deg = estimate.heading_deg,
      .q = {q.w(), q.x(), q.y(), q.z()},
      .bias_dps = {estimate.bias_dps.x(), estimate.bias_dps.y(), estimate.bias_dps.z()},
      .heading_sigma_deg = estimate.heading_sigma_deg,
      .segment_index = estimate.segment_index,
  });
}

void EstimatesWriter::release(std::uint64_t segment_index, bool still) {
  std::size_t released = 0;
  for (const Row& row : waiting_) {
    if (row.segment_index > segment_index) break;
    write(row, still && row.segment_index == segment_index);
    ++released;
  }
  waiting_.erase(waiting_.begin(), waiting_.begin() + static_cast<std::ptrdiff_t>(released));
}

void EstimatesWriter::finish() {
  for (const Row& row : waiting_) write(row, false);
  waiting_.clear();
  out_.flush();
}

void EstimatesWriter::write(const Row& row, bool still) {
  out_.number(row.t_s, 6).number(row.heading_deg, 6);
  for (double component : row.q) out_.number(component, 9);
  for (double bias : row.bias_dps) out_.number(bias, 6);
  out_.number(row.heading_sigma_deg, 6).integer(still ? 1 : 0);
  out_.end_line();
  ++rows_written_;
}

}  // namespace headingd::app
