// The L3GD20H driver against the register-level simulator: init sequence, decoding, FIFO
// draining in both stream modes, overruns, bus faults, a chip that resets itself, stuck
// output, and the time stamps.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "hw/l3gd20h.hpp"
#include "hw/l3gd20h_registers.hpp"
#include "sim/l3gd20h_sim.hpp"

using namespace headingd::drivers;
using headingd::core::Sample;

namespace {

// x counts samples (wrapping at int16), y and z a fixed pattern with a sign change.
RawSample counter(std::uint64_t index) {
  return {static_cast<std::int16_t>(static_cast<std::uint16_t>(index & 0xFFFF)),
          static_cast<std::int16_t>(-1000 - static_cast<int>(index % 7)), static_cast<std::int16_t>(12345)};
}

std::vector<Sample> collect(L3gd20h& driver, std::size_t count) {
  std::vector<Sample> all;
  std::vector<Sample> batch(50);
  while (all.size() < count) {
    // Never ask for more than wanted: what the driver hands out is gone from it.
    const auto n = driver.read(std::span(batch).first(std::min<std::size_t>(batch.size(), count - all.size())));
    all.insert(all.end(), batch.begin(), batch.begin() + static_cast<long>(n));
  }
  return all;
}

std::int64_t x_lsb(const Sample& s, double sensitivity) { return std::llround(s.rate_dps.x() / sensitivity); }

}  // namespace

TEST(L3gd20h, InitSequenceWritesExactlyTheDocumentedRegisters) {
  L3gd20hSimulator sim({}, counter);
  L3gd20h driver(sim, sim, {});
  driver.start();
  using namespace l3gd20h;
  const std::vector<std::pair<int, int>> expected = {
      {LOW_ODR, 0x04},                       // software reset
      {CTRL1, 0x07},                         // power-down while configuring
      {CTRL2, 0x00},     {CTRL3, 0x04},      // watermark on INT2
      {CTRL4, 0x80},                         // BDU, little-endian, +-245 dps
      {LOW_ODR, 0x00},                       // INT2 active high, Low_ODR off
      {FIFO_CTRL, 0x00},                     // bypass clears the FIFO
      {CTRL5, 0x40},                         // FIFO enable
      {FIFO_CTRL, 0xC8},                     // dynamic stream, watermark 8
      {CTRL1, 0xAF},                         // 400 Hz, BW 2, power on, XYZ
      {FIFO_CTRL, 0x00}, {FIFO_CTRL, 0xC8},  // restart the FIFO after Ton
  };
  ASSERT_EQ(sim.writes().size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(sim.writes()[i].reg, expected[i].first) << "write " << i;
    EXPECT_EQ(sim.writes()[i].value, expected[i].second) << "write " << i;
  }
  EXPECT_EQ(sim.reserved_writes(), 0u);
}

TEST(L3gd20h, WrongChipIsRefusedByName) {
  L3gd20hSimSettings settings;
  settings.who_am_i = 0xD4;
  L3gd20hSimulator sim(settings, counter);
  L3gd20h driver(sim, sim, {});
  try {
    driver.start();
    FAIL();
  } catch (const DriverError& error) {
    EXPECT_NE(std::string(error.what()).find("WHO_AM_I is 0xD4, not 0xD7"), std::string::npos) << error.what();
  }
}

TEST(L3gd20hSimulator, ARateErrorThatStopsTheChipIsRefused) {
  for (const double error : {-1.0, -2.0, 1.0, std::nan("")}) {
    L3gd20hSimSettings settings;
    settings.rate_error = error;
    EXPECT_THROW(L3gd20hSimulator(settings, counter), std::invalid_argument) << error;
    EXPECT_THROW(L3gd20hSimulator(settings, "still", 1), std::invalid_argument) << error;
  }
  L3gd20hSimSettings settings;
  settings.rate_error = -0.15;  // the datasheet's ODR tolerance
  EXPECT_NO_THROW(L3gd20hSimulator(settings, "still", 1));
}

TEST(L3gd20h, DecodesSignScaleAndOrderForEachFullScale) {
  for (const auto& [fs, sensitivity] : {std::pair{245, 0.00875}, {500, 0.0175}, {2000, 0.070}}) {
    L3gd20hSimulator sim({}, [](std::uint64_t i) {
      return RawSample{static_cast<std::int16_t>(1000 + (i % 2)), -2000,
                       static_cast<std::int16_t>(i % 2 ? 32767 : -32768)};
    });
    L3gd20hSettings settings;
    settings.full_scale_dps = fs;
    L3gd20h driver(sim, sim, settings);
    const auto samples = collect(driver, 100);
    for (const auto& s : samples) {
      const double x_lsb_value = std::round(s.rate_dps.x() / sensitivity);
      ASSERT_TRUE(x_lsb_value == 1000 || x_lsb_value == 1001) << fs;
      ASSERT_NEAR(s.rate_dps.y(), -2000 * sensitivity, 1e-9) << fs;
      ASSERT_TRUE(std::abs(s.rate_dps.z() - 32767 * sensitivity) < 1e-9 ||
                  std::abs(s.rate_dps.z() + 32768 * sensitivity) < 1e-9);
    }
    EXPECT_EQ(sim.reg(l3gd20h::CTRL4) & 0x30, fs == 245 ? 0x00 : fs == 500 ? 0x10 : 0x20);
  }
}

class FifoModes : public ::testing::TestWithParam<bool> {};

TEST_P(FifoModes, NoSampleLostOrRepeatedOver100kSamples) {
  L3gd20hSimulator sim({}, counter);
  L3gd20hSettings settings;
  settings.dynamic_stream = GetParam();
  L3gd20h driver(sim, sim, settings);
  const auto samples = collect(driver, 100'000);
  // Every sample arrives once, in order (the first after the FIFO restart is dropped, DS 4.2).
  auto expected = static_cast<std::uint16_t>(x_lsb(samples[0], 0.00875));
  for (std::size_t i = 0; i < samples.size(); ++i, ++expected) {
    ASSERT_EQ(static_cast<std::uint16_t>(x_lsb(samples[i], 0.00875)), expected) << "sample " << i;
    if (i > 0) {
      ASSERT_GT(samples[i].t_s, samples[i - 1].t_s);
    }
  }
  EXPECT_EQ(driver.counters().lost_samples, 0u);
  EXPECT_EQ(driver.counters().overruns, 0u);
  EXPECT_EQ(sim.overwritten(), 0u);
}

// Counts the transfers that read FIFO_SRC, passing everything on to the simulated chip.
class CountingBus final : public I2cBus {
 public:
  explicit CountingBus(I2cBus& bus) : bus_(bus) {}
  void write_read(std::uint8_t address, std::span<const std::uint8_t> tx, std::span<std::uint8_t> rx) override {
    if (!tx.empty() && (tx[0] & 0x7F) == l3gd20h::FIFO_SRC) ++fifo_src_reads;
    bus_.write_read(address, tx, rx);
  }
  void write(std::uint8_t address, std::span<const std::uint8_t> tx) override { bus_.write(address, tx); }
  std::string describe() const override { return bus_.describe(); }
  std::uint64_t fifo_src_reads = 0;

 private:
  I2cBus& bus_;
};

TEST_P(FifoModes, OneFifoStatusReadPerWakeUp) {
  // After the burst the FIFO holds only what arrived during it, below the watermark: the next
  // edge brings it, and no second FIFO_SRC read is needed to find that out.
  L3gd20hSimulator sim({}, counter);
  CountingBus bus(sim);
  L3gd20hSettings settings;
  settings.dynamic_stream = GetParam();
  L3gd20h driver(bus, sim, settings);
  const auto samples = collect(driver, 20'000);
  const auto wakeups = driver.counters().wakeups;
  ASSERT_GT(wakeups, 2000u);
  EXPECT_LE(bus.fifo_src_reads, wakeups + wakeups / 100) << "FIFO_SRC reads " << bus.fifo_src_reads;
  EXPECT_EQ(driver.counters().timeouts, 0u) << "every wake-up came from an edge";
  EXPECT_EQ(driver.counters().lost_samples, 0u);
}

INSTANTIATE_TEST_SUITE_P(L3gd20h, FifoModes, ::testing::Values(true, false),
                         [](const ::testing::TestParamInfo<bool>& param_info) {
                           return param_info.param ? "DynamicStream" : "StreamWithRepeatPitfall";
                         });

TEST(L3gd20h, OverrunCountsLostSamplesAndLeavesAGapInTime) {
  L3gd20hSimulator sim({}, counter);
  L3gd20h driver(sim, sim, {});
  auto before = collect(driver, 2000);
  sim.inject_stall(200'000'000);  // the host is 200 ms late: the 32-deep FIFO (84 ms) overflows
  auto after = collect(driver, 500);
  EXPECT_GE(driver.counters().overruns, 1u);
  ASSERT_GT(driver.counters().lost_samples, 0u);
  // The counter in x shows exactly the lost samples; the time stamps show the same gap.
  std::vector<Sample> all = before;
  all.insert(all.end(), after.begin(), after.end());
  std::uint64_t jumps = 0;
  double gap_s = 0.0;
  for (std::size_t i = 1; i < all.size(); ++i) {
    const auto step = static_cast<std::uint16_t>(x_lsb(all[i], 0.00875) - x_lsb(all[i - 1], 0.00875));
    if (step != 1) {
      jumps += step - 1u;
      gap_s = all[i].t_s - all[i - 1].t_s;
    }
    ASSERT_GT(all[i].t_s, all[i - 1].t_s);
  }
  EXPECT_EQ(jumps, driver.counters().lost_samples);
  EXPECT_EQ(jumps, sim.overwritten());
  EXPECT_NEAR(gap_s, static_cast<double>(jumps + 1) / sim.actual_rate_hz(), 1.5 / sim.actual_rate_hz());
}

TEST(L3gd20h, NackAndTimeoutAreRetriedCountedNeverFatal) {
  L3gd20hSimulator sim({}, counter);
  L3gd20h driver(sim, sim, {});
  collect(driver, 1000);
  sim.inject_nack(2);  // within the retries
  collect(driver, 1000);
  EXPECT_GE(driver.counters().bus_errors, 2u);
  EXPECT_EQ(driver.counters().recoveries, 0u);
  sim.inject_timeout(6);  // past the retries: the driver sets the chip up again
  const auto after = collect(driver, 1000);
  EXPECT_GE(driver.counters().bus_errors, 8u);
  EXPECT_GE(driver.counters().recoveries, 1u);
  EXPECT_EQ(after.size(), 1000u);
}

TEST(L3gd20h, SpontaneousResetIsDetectedAndRecoveredWithinASecond) {
  L3gd20hSimulator sim({}, counter);
  L3gd20h driver(sim, sim, {});
  const auto before = collect(driver, 3000);
  sim.inject_reset();  // brown-out: power-down, FIFO off, registers at defaults
  const auto after = collect(driver, 1000);
  EXPECT_GE(driver.counters().chip_resets + driver.counters().recoveries, 1u);
  EXPECT_LT(after.front().t_s - before.back().t_s, 1.0);
  EXPECT_EQ(sim.reg(l3gd20h::CTRL5), 0x40) << "configured again";
}

TEST(L3gd20h, StuckOutputIsNoticed) {
  L3gd20hSimulator sim({}, counter);
  L3gd20h driver(sim, sim, {});
  collect(driver, 1000);
  sim.inject_stuck(3'000'000'000);
  collect(driver, 3000);
  EXPECT_GE(driver.counters().stuck_events, 1u);
}

TEST(L3gd20h, TimeStampsIncreaseAndRateIsLearnedWithinATenthOfAPercent) {
  L3gd20hSimSettings settings;
  settings.rate_error = 0.07;  // a fast part: 405 Hz instead of 378.8
  L3gd20hSimulator sim(settings, counter);
  L3gd20h driver(sim, sim, {});
  const auto samples = collect(driver, static_cast<std::size_t>(10.5 * sim.actual_rate_hz()));
  for (std::size_t i = 1; i < samples.size(); ++i) ASSERT_GT(samples[i].t_s, samples[i - 1].t_s);
  EXPECT_NEAR(driver.rate_hz() / sim.actual_rate_hz(), 1.0, 0.001);
  const double span_s = samples.back().t_s - samples.front().t_s;
  EXPECT_NEAR(span_s * sim.actual_rate_hz(), static_cast<double>(samples.size() - 1), 2.0);
}

TEST(L3gd20h, StopFlagEndsReading) {
  L3gd20hSimulator sim({}, counter);
  L3gd20h driver(sim, sim, {});
  std::atomic<bool> stop{true};
  driver.set_stop_flag(&stop);
  std::vector<Sample> batch(10);
  EXPECT_EQ(driver.read(batch), 0u);
}

TEST(L3gd20h, SettingsAreValidated) {
  L3gd20hSimulator sim({}, counter);
  L3gd20hSettings settings;
  settings.full_scale_dps = 300;
  EXPECT_THROW(L3gd20h(sim, sim, settings), DriverError);
}

// --sim-realtime: the simulated chip never runs ahead of the wall clock, bus time included (it
// ran 6 % fast when only the waits were slept). Slower is allowed: a loaded machine only delays.
TEST(L3gd20hSimulator, RealtimeNeverRunsAheadOfTheWallClock) {
  L3gd20hSimulator sim({}, "still", 1);
  sim.set_realtime(true);
  L3gd20h driver(sim, sim, {});
  driver.start();
  std::vector<headingd::core::Sample> batch(64);
  const auto start = std::chrono::steady_clock::now();
  double first_t = NAN, last_t = NAN;
  while (std::isnan(first_t) || last_t - first_t < 2.0) {
    const auto n = driver.read(batch);
    if (std::isnan(first_t)) first_t = batch[0].t_s;
    last_t = batch[n - 1].t_s;
  }
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_GE(wall_s, 0.99 * (last_t - first_t)) << "simulated " << last_t - first_t << " s in " << wall_s << " s";
}
