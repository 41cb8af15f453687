#include "pipeline/wall_stamps.hpp"

#include <algorithm>
#include <utility>

namespace headingd::pipeline {

WallStamps::WallStamps(WallClock wall) : wall_(std::move(wall)) {}

double WallStamps::stamp(double t_s) {
  const double candidate_s = wall_() - t_s;
  if (!started_) {
    started_ = true;
    offset_s_ = target_s_ = block_min_s_ = candidate_s;
    block_start_s_ = previous_t_s_ = t_s;
    return t_s + offset_s_;
  }
  const double dt_s = std::max(0.0, t_s - previous_t_s_);
  previous_t_s_ = t_s;
  block_min_s_ = std::min(block_min_s_, candidate_s);
  if (t_s - block_start_s_ >= kBlockS) {
    if (block_min_s_ > offset_s_)
      offset_s_ = target_s_ = block_min_s_;  // forward: at once, stamps jump ahead
    else
      target_s_ = block_min_s_;  // back: slew towards it
    block_start_s_ = t_s;
    block_min_s_ = candidate_s;
  }
  if (offset_s_ > target_s_) offset_s_ = std::max(target_s_, offset_s_ - kSlewDownPerS * dt_s);
  return t_s + offset_s_;
}

}  // namespace headingd::pipeline
