#pragma once
// Writes estimates in the replay CSV contract:
//   time_s,heading_deg,qw,qx,qy,qz,bias_x_dps,bias_y_dps,bias_z_dps,heading_sigma_deg,still
// at a chosen output rate. `still` says whether the sample's segment was accepted as
// still, which is known only when that segment closes, so rows wait (at most one segment)
// until their segment is judged. The wait buffer is reserved once.
#include <cstdint>
#include <vector>

#include "core/estimate.hpp"
#include "io/csv_out.hpp"

namespace headingd::app {

inline constexpr const char* kEstimatesHeader =
    "time_s,heading_deg,qw,qx,qy,qz,bias_x_dps,bias_y_dps,bias_z_dps,heading_sigma_deg,still";

class EstimatesWriter {
 public:
  // output_rate_hz 0 writes every sample. `rows_per_segment` sizes the wait buffer.
  EstimatesWriter(CsvOut& out, double output_rate_hz, std::size_t rows_per_segment);

  void add(const core::Estimate& estimate);
  // The earliest sample time that may be due for a row (minus infinity: every sample is);
  // add() for an earlier one does nothing unless the estimate closes a segment.
  double next_due_s() const;
  // Writes rows still waiting (their segment never closed, so still = 0) and flushes.
  void finish();
  std::uint64_t rows_written() const { return rows_written_; }

 private:
  struct Row {
    double t_s;
    double heading_deg;
    double q[4];
    double bias_dps[3];
    double heading_sigma_deg;
    std::uint64_t segment_index;
  };
  bool due(double t_s);
  void release(std::uint64_t segment_index, bool still);
  void write(const Row& row, bool still);

  CsvOut& out_;
  double period_s_;
  double grid_origin_s_ = 0.0;
  std::uint64_t grid_step_ = 0;
  double next_output_s_ = 0.0;
  bool first_ = true;
  std::vector<Row> waiting_;
  std::uint64_t rows_written_ = 0;
};

}  // namespace headingd::app
