#include "core/temperature_reading.hpp"

#include <algorithm>
#include <cmath>

namespace headingd::core {
namespace {

constexpr double kWholeTolerance = 1e-9;  // a reading written as 25.000000 is still whole
constexpr double kRefreshS = 1.0;         // the L3GD20H refreshes OUT_TEMP at 1 Hz

}  // namespace

double TemperatureReading::take(double t_s, double reading_c) {
  if (!std::isfinite(reading_c) || !whole_degrees_) return reading_c;
  if (std::abs(reading_c - std::round(reading_c)) > kWholeTolerance) {
    whole_degrees_ = false;  // a fine reading: nothing to reconstruct, now or later
    return reading_c;
  }
  if (!have_reading_) {
    have_reading_ = true;
    reading_c_ = reading_c;
    held_c_ = reading_c;
    held_t_s_ = t_s;
    crossing_t_s_ = t_s;  // no crossing yet: the gap to the first one counts from here
    return held_c_;
  }
  if (reading_c != reading_c_) {
    const int direction = reading_c > reading_c_ ? 1 : -1;
    // The midpoint next to the new reading: a jump of two degrees crossed the last one now.
    const double crossing_c = reading_c - 0.5 * direction;
    const bool onwards = have_crossing_ && direction == direction_ && t_s > crossing_t_s_;
    const double gap_s = std::max(kRefreshS, t_s - crossing_t_s_);
    // A step back is a turn when the temperature had a rate: it went beyond the midpoint and
    // came back, and it leaves about as fast as it came, the more so the longer it stayed
    // beyond (a gap of a whole step's time at the last rate: a turn at full speed, a heater
    // switching; a gap of seconds: a temperature dithering at the midpoint, next to no rate).
    const bool turn = have_crossing_ && direction != direction_ && rate_c_per_s_ != 0.0;
    const double last_rate = std::abs(rate_c_per_s_);
    rate_c_per_s_ = onwards ? (crossing_c - crossing_c_) / (t_s - crossing_t_s_)
                    : turn  ? direction * last_rate * std::min(1.0, gap_s * last_rate)
                            : 0.0;
    hold_s_ = 2.0 * gap_s;
    have_crossing_ = true;
    crossing_t_s_ = t_s;
    crossing_c_ = crossing_c;
    direction_ = direction;
    reading_c_ = reading_c;
    held_c_ = value_at(t_s);
    held_t_s_ = t_s;
    return held_c_;
  }
  if (t_s - held_t_s_ >= kRefreshS || t_s < held_t_s_) {
    held_c_ = value_at(t_s);
    held_t_s_ = t_s;
  }
  return held_c_;
}

double TemperatureReading::value_at(double t_s) const {
  if (!have_crossing_) return reading_c_;
  const double since_s = std::max(0.0, t_s - crossing_t_s_);
  if (rate_c_per_s_ == 0.0) {
    // A first step, or a step back with no rate before it: no rate to follow. A temperature
    // dithering about the midpoint steps again within about the gap before this step (twice
    // it: the time spent on either side varies), so the midpoint holds that long; a step that
    // does not come says the temperature has moved into the reading's band and, which side
    // unknown, its middle becomes the best guess.
    if (since_s <= hold_s_) return crossing_c_;
    return reading_c_ - 0.5 * direction_ * std::exp(-(since_s - hold_s_) / hold_s_);
  }
  // At the last rate the next midpoint is due after `due_s`. Until then the temperature moves
  // on at that rate; a step that is overdue says it has slowed, and the further overdue, the
  // more the middle of the reading's band (where a temperature that stopped is likeliest) is
  // the best guess.
  const double due_s = 1.0 / std::abs(rate_c_per_s_);
  const double value_c = since_s <= due_s ? crossing_c_ + rate_c_per_s_ * since_s
                                          : reading_c_ + 0.5 * direction_ * std::exp(-(since_s - due_s) / due_s);
  return std::clamp(value_c, reading_c_ - 0.5, reading_c_ + 0.5);
}

}  // namespace headingd::core
