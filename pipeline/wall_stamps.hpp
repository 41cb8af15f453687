#pragma once
// Published stamps are wall-clock time (UTC seconds since 1970, as ROS header stamps), while
// samples keep their monotonic driver time inside the pipeline. This maps one to the other with
// an offset that follows the system clock (NTP/chrony steps and slews) and never makes the
// stamps go backwards:
//  - the offset is the smallest (wall now - sample time) seen over half a second, which is the
//    sample with the least delay between the chip and us;
//  - when that rises (the wall clock stepped or slewed forward), the offset rises with it at
//    once: a forward step shows in the stamps within a second;
//  - when it falls (the wall clock stepped back), the offset slews down at kSlewDownPerS seconds
//    per second of sample time, so stamps keep increasing (at 90 % of their pace) until they
//    reach the new clock: a 10 s step back is caught up in 100 s.
#include <functional>

namespace headingd::pipeline {

inline constexpr double kSlewDownPerS = 0.1;  // s of offset per s of sample time, < 1
inline constexpr double kBlockS = 0.5;        // sample time over which the least delay is taken

class WallStamps {
 public:
  using WallClock = std::function<double()>;  // wall-clock now, s since 1970
  explicit WallStamps(WallClock wall);
  // The stamp for a sample taken at monotonic time t_s and handled just now.
  double stamp(double t_s);
  double offset_s() const { return offset_s_; }

 private:
  WallClock wall_;
  bool started_ = false;
  double offset_s_ = 0.0;
  double target_s_ = 0.0;  // where a downward slew is heading
  double block_start_s_ = 0.0;
  double block_min_s_ = 0.0;  // least (wall - t) in the block under way
  double previous_t_s_ = 0.0;
};

}  // namespace headingd::pipeline
