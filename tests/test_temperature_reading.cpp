// TemperatureReading: the estimator's temperature from a sensor that reports whole degrees
// (the L3GD20H's OUT_TEMP), and from one that does not.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/level_slope.hpp"
#include "core/temperature_reading.hpp"
#include "sim/chip_thermometer.hpp"

using headingd::core::LevelSlope;
using headingd::core::TemperatureReading;
using headingd::core::Vec3;

namespace {

struct Errors {
  double reconstructed_rms = 0.0, rounded_rms = 0.0, reconstructed_max = 0.0;
  double beyond_reading_max = 0.0;  // the value's largest distance from the reading itself
};

// A warm-up of `rise_c` with time constant `tau_s`, read at 50 Hz for two hours; errors counted
// from the second step on (before it there is no rate to follow).
template <typename Truth>
Errors errors_on(Truth truth_c) {
  TemperatureReading reading;
  headingd::drivers::ChipThermometer chip;
  double sum_reconstructed = 0.0, sum_rounded = 0.0, previous_c = std::numeric_limits<double>::quiet_NaN();
  int steps = 0;
  long counted = 0;
  Errors e;
  for (long i = 0; i < 2L * 3600 * 50; ++i) {
    const double t_s = static_cast<double>(i) / 50.0;
    const double true_c = truth_c(t_s);
    const double read_c = chip.read(t_s, true_c);
    const double value_c = reading.take(t_s, read_c);
    if (!std::isnan(previous_c) && read_c != previous_c) ++steps;
    previous_c = read_c;
    if (steps < 2) continue;
    ++counted;
    sum_reconstructed += (value_c - true_c) * (value_c - true_c);
    sum_rounded += (read_c - true_c) * (read_c - true_c);
    e.reconstructed_max = std::max(e.reconstructed_max, std::abs(value_c - true_c));
    e.beyond_reading_max = std::max(e.beyond_reading_max, std::abs(value_c - read_c));
  }
  e.reconstructed_rms = std::sqrt(sum_reconstructed / static_cast<double>(counted));
  e.rounded_rms = std::sqrt(sum_rounded / static_cast<double>(counted));
  return e;
}

}  // namespace

TEST(TemperatureReading, FineReadingsPassThroughUnchanged) {
  TemperatureReading reading;
  // A first reading that happens to be whole, then fine ones: nothing is reconstructed.
  EXPECT_EQ(reading.take(0.0, 22.0), 22.0);
  EXPECT_EQ(reading.take(0.01, 22.000013), 22.000013);
  EXPECT_FALSE(reading.whole_degrees());
  EXPECT_EQ(reading.variance_c2(), 0.0);
  EXPECT_EQ(reading.take(0.02, 23.0), 23.0) << "once fine, always passed through";
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(std::isnan(reading.take(0.03, nan)));
}

TEST(TemperatureReading, AWarmUpReadInWholeDegreesIsFollowedBetweenTheSteps) {
  // 10 degC over an hour's time constant: the reading is 0.29 degC off in RMS (a uniform half
  // degree); the reconstruction follows the ramp between its steps.
  const Errors slow = errors_on([](double t) { return 20.3 + 10.0 * (1.0 - std::exp(-t / 3600.0)); });
  EXPECT_NEAR(slow.rounded_rms, 0.29, 0.02);
  EXPECT_LT(slow.reconstructed_rms, 0.6 * slow.rounded_rms);
  EXPECT_LT(slow.reconstructed_max, 0.5);
  EXPECT_LT(slow.beyond_reading_max, 0.5 + 1e-9) << "never beyond the reading's own band";
  // A steady ramp of 5 degC/h: the steps come on time and the value is the ramp.
  const Errors ramp = errors_on([](double t) { return 18.2 + 5.0 * t / 3600.0; });
  EXPECT_LT(ramp.reconstructed_max, 0.01);
  // A warm-up that levels off within the run: overdue steps bring the value back to the middle
  // of the reading, no worse than the reading itself in RMS. (While a warm-up slows, the value
  // runs ahead of it until the step it expects is overdue: up to 0.56 degC off, where the
  // reading is 0.06 off; never outside the reading's band.)
  const Errors settles = errors_on([](double t) { return 20.3 + 3.0 * (1.0 - std::exp(-t / 900.0)); });
  EXPECT_LT(settles.reconstructed_rms, 1.05 * settles.rounded_rms);
  EXPECT_LT(settles.beyond_reading_max, 0.5 + 1e-9);
}

TEST(TemperatureReading, ATemperatureThatTurnsOrJittersIsFollowedNoWorseThanItsReading) {
  // A temperature that swings +-1.5 degC over an hour turns back inside a reading: the step
  // back is a turn, taken at the last rate (scaled by how long the temperature stayed beyond
  // the midpoint), not a midpoint held for a whole degree: 0.27 degC RMS; held, 0.37; reading 0.29.
  const Errors swings = errors_on([](double t) { return 25.2 + 1.5 * std::sin(t / 600.0); });
  EXPECT_LT(swings.reconstructed_rms, swings.rounded_rms);
  EXPECT_LT(swings.beyond_reading_max, 0.5 + 1e-9);
  // A ramp of 3 degC/h read with +-0.2 degC of jitter: each crossing dithers; steps back that
  // are not followed by another settle into the reading: 0.21 degC RMS; held, 0.43; reading 0.34.
  unsigned state = 1;
  const Errors jitter = errors_on([&state](double t) {
    state = state * 1103515245U + 12345U;
    const double uniform = static_cast<double>((state >> 8U) & 0xffffU) / 65536.0 - 0.5;
    return 20.0 + 3.0 * t / 3600.0 + 0.4 * uniform;
  });
  EXPECT_LT(jitter.reconstructed_rms, 0.7 * jitter.rounded_rms);
  EXPECT_LT(jitter.beyond_reading_max, 0.5 + 1e-9);
}

TEST(TemperatureReading, ATemperatureDitheringAboutAMidpointIsHeldThere) {
  TemperatureReading reading;
  EXPECT_EQ(reading.take(0.0, 25.0), 25.0);
  // The true temperature hovers at 25.5: the reading toggles between 25 and 26.
  for (int i = 1; i < 600; ++i) {
    const double value = reading.take(i, i % 7 < 3 ? 26.0 : 25.0);
    EXPECT_EQ(value, 25.5) << "at " << i << " s";
  }
}

TEST(TemperatureReading, AskingTwiceForOneSampleGivesTheSame) {
  // The estimator's fast path may ask for a sample, stop before it, and ask again.
  TemperatureReading once, twice;
  for (int i = 0; i < 20000; ++i) {
    const double t = i * 0.25;
    const double read = std::round(20.0 + t / 700.0);
    const double a = once.take(t, read);
    twice.take(t, read);
    EXPECT_EQ(twice.take(t, read), a) << "at " << t << " s";
  }
  EXPECT_TRUE(once.whole_degrees());
  EXPECT_NEAR(once.variance_c2(), 1.0 / 12.0, 1e-15);
}

TEST(LevelSlope, WholeDegreeTemperaturesWidenTheSlopesSigma) {
  // A run over 1.5 degC read in whole degrees: the temperatures' own error (1/12 degC^2) adds
  // the slope's share to its variance, so a slope from one degree of spread refutes little.
  LevelSlope slope;
  for (int i = 0; i < 30; ++i) {
    const double temp = 25.0 + 1.5 * i / 29.0;
    slope.add(3.0, temp, Vec3(0.0, 0.0, -0.45 - 0.005 * (temp - 25.0)));
  }
  const Vec3 white = Vec3::Constant(1e-6);
  LevelSlope::Fit exact, read;
  ASSERT_TRUE(slope.fit(white, exact));
  ASSERT_TRUE(slope.fit(white, read, 1.0 / 12.0));
  EXPECT_NEAR(read.slope_dps_per_c.z(), exact.slope_dps_per_c.z(), 1e-15);
  // sum_w / sxx = 1 / var(T), var(T) = 1.5^2 / 12 (nearly): the added sd is about |slope| / 1.5.
  const double added = read.slope_variance.z() - exact.slope_variance.z();
  EXPECT_NEAR(std::sqrt(added), 0.005 / 1.5, 0.0003);
}

TEST(TemperatureReading, ATemperatureThatTurnsBackAndRestsSettlesIntoItsReading) {
  // Warming through 25.5 degC (reading 25 -> 26), turning back below it within a minute (26 ->
  // 25) and resting at 25.1 for an hour: the step back puts the value at the midpoint, and with
  // no step after it the value settles to the middle of the reading instead of staying 0.4 off.
  TemperatureReading reading;
  headingd::drivers::ChipThermometer chip;
  const auto truth_c = [](double t) {
    if (t < 600.0) return 24.9 + 0.7 * t / 600.0;           // to 25.6 at 600 s
    if (t < 660.0) return 25.6 - 0.5 * (t - 600.0) / 60.0;  // back to 25.1 at 660 s
    return 25.1;
  };
  double value_c = 0.0;
  double worst_after_c = 0.0;
  for (long i = 0; i < 3600L * 50; ++i) {
    const double t_s = static_cast<double>(i) / 50.0;
    value_c = reading.take(t_s, chip.read(t_s, truth_c(t_s)));
    EXPECT_LE(std::abs(value_c - 25.0), 0.5 + 1e-9) << "at " << t_s << " s";
    if (t_s > 1800.0) worst_after_c = std::max(worst_after_c, std::abs(value_c - truth_c(t_s)));
  }
  EXPECT_NEAR(value_c, 25.0, 0.01) << "settled to the middle of the reading";
  EXPECT_LT(worst_after_c, 0.11);
}
