#pragma once
// The floor of heading error for a simulated recording: what a perfect bias estimator with
// perfect stillness knowledge would output. From the recording and the simulator's truth (its
// true bias and moving flag), the z rate less the true bias, integrated only while truly
// moving (at 10 Hz: any truth row either side of a sample saying so). What remains in it against the truth
// (scale-factor error, noise while moving) no bias estimator can remove; an estimator's excess error is its heading
// less this one.
#include <string>

#include "tools/heading_score.hpp"

namespace headingd::app {

struct Truth {
  TimeSeries heading;  // heading_deg
  std::vector<double> bias_z_dps;
  std::vector<double> moving;  // 0 or 1, at the heading's instants
};

// Reads truth.csv (time_s, heading_deg, bias_z_dps, moving). Throws drivers::InputError.
Truth read_truth(const std::string& path);

// The floor heading at the recording's samples, one point per truth interval (about 10 Hz),
// starting from the true heading at the first sample. Throws drivers::InputError/OpenError.
TimeSeries floor_heading(const std::string& recording, const Truth& truth);

}  // namespace headingd::app
