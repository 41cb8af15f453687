#pragma once
// The temperature the estimator works with, from what the sensor reports. The L3GD20H reports
// whole degrees (OUT_TEMP: 8 bits, -1 LSB/degC, refreshed at 1 Hz; datasheet section 7.8 and
// Table 5), so a warm-up reaches the estimator as a staircase of 1 degC steps: a temperature
// model then moves the bias by a whole degree's worth at once, a still segment's temperature
// is wrong by up to half a degree, and a stop's own slope against temperature (a refutation)
// sees one or two steps where the true temperature moved smoothly.
//
// A step between two whole readings says that the true temperature crossed the midpoint
// between them at about that moment. Between crossings the temperature is taken to move at the
// rate of the last two crossings in the same direction until the next step is due, and then,
// the step overdue, to settle towards the middle of the reading; always within the half degree
// the reading allows. A step back after a rate is a turn: the temperature leaves at the last
// rate, scaled down by how briefly it stayed beyond the midpoint (a dithering one stays seconds).
// A first step, or a step back without a rate, holds the midpoint for twice the gap before it
// and then, with no further step, settles towards the middle of the reading as an overdue step
// does. On a warm-up of 10 degC with an hour's time constant this is within 0.10 degC RMS of the
// true temperature where the reading is 0.29 degC off; on a steady ramp, 0.003; on a swing of
// +-1.5 degC, 0.27 (reading 0.29); on a ramp with +-0.2 degC of jitter, 0.21 (reading 0.34);
// where the temperature levels off, no better than the reading
// (tests/test_temperature_reading.cpp).
// Readings that are not all whole numbers (a simulator, an IIO sensor with a fine scale) pass
// through unchanged, as does an unknown (NaN) one.

namespace headingd::core {

class TemperatureReading {
 public:
  // The temperature for a sample at t_s with this reading. Calling it again for the same
  // sample gives the same value (the estimator's fast path may ask twice); the value moves at
  // most once a second between steps, so runs of samples share it.
  double take(double t_s, double reading_c);

  bool whole_degrees() const { return whole_degrees_; }
  // The variance of a temperature's own error, degC^2: a uniform half degree either way for
  // whole-degree readings (reconstructed or not, the reading allows no better), else none.
  double variance_c2() const { return whole_degrees_ && have_reading_ ? 1.0 / 12.0 : 0.0; }

 private:
  double value_at(double t_s) const;

  bool whole_degrees_ = true;  // every finite reading so far a whole number
  bool have_reading_ = false;
  double reading_c_ = 0.0;
  bool have_crossing_ = false;
  double crossing_t_s_ = 0.0;
  double crossing_c_ = 0.0;
  int direction_ = 0;          // +1 warming, -1 cooling: of the last crossing
  double rate_c_per_s_ = 0.0;  // between the last two crossings in the same direction
  double hold_s_ = 0.0;        // how long a step without a rate keeps the midpoint
  double held_c_ = 0.0;        // the value handed out, refreshed at most once a second
  double held_t_s_ = 0.0;
};

}  // namespace headingd::core
