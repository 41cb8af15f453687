#pragma once
// ST L3GD20H gyro over I2C, woken by its FIFO watermark on DRDY/INT2 (docs/l3gd20h.md,
// sections 4-5): software reset and full configuration at start, FIFO in dynamic stream (or
// stream) mode drained with one burst read per pass until empty, temperature and a register
// read-back every second (a chip that reset itself after a brown-out is noticed and set up
// again), bus errors retried and counted, never fatal. Sample time stamps come from the edge
// time stamps and the FIFO counts, with the real output rate estimated online.
#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>

#include "core/sample_source.hpp"
#include "hw/data_ready.hpp"
#include "hw/i2c_bus.hpp"
#include "hw/sample_clock.hpp"

namespace headingd::drivers {

struct L3gd20hSettings {
  std::uint8_t address = 0x6B;   // 0x6A with SDO/SA0 low
  int rate_hz = 400;             // nominal ODR: 100, 200, 400, 800 (real: 94.7 ... 757.6 Hz)
  int bandwidth = 2;             // CTRL1.BW 0..3; at 400 Hz: 20, 25, 50, 110 Hz LPF2 cut-off
  int full_scale_dps = 245;      // 245, 500, 2000
  int watermark = 8;             // FIFO threshold, 1..30; the edge comes with threshold + 1 samples
                                 // (dynamic stream): every 18.5 ms at 378.8 Hz, more often than the
                                 // 50 Hz Orientation (bench/sample_age.sh)
  bool dynamic_stream = true;    // DS: for hosts that cannot read within one ODR period
  bool int2_active_low = false;  // LOW_ODR.DRDY_HL
  int max_retries = 3;           // per transaction, before the chip is set up again
  double housekeeping_s = 1.0;   // temperature and register read-back period
  double stuck_s = 2.0;          // identical output this long means the chip is stuck
  // No sample for this long while every recovery fails: the sensor is taken for dead and
  // read() throws, so the service exits and systemd can act (0: retry for ever).
  double give_up_s = 30.0;
};

// Empty when usable, else names the field and the allowed values.
std::optional<std::string> validate(const L3gd20hSettings& settings);

class DriverError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct DriverCounters {
  std::uint64_t samples = 0;       // delivered
  std::uint64_t lost_samples = 0;  // overwritten in the FIFO before they were read
  std::uint64_t overruns = 0;
  std::uint64_t bus_errors = 0;   // failed transactions (each retried)
  std::uint64_t recoveries = 0;   // chip set up again after a fault
  std::uint64_t chip_resets = 0;  // the read-back found the chip's registers at their defaults
  std::uint64_t stuck_events = 0;
  std::uint64_t wakeups = 0;
  std::uint64_t timeouts = 0;  // no edge in time: polled anyway
};

class L3gd20h final : public core::SampleSource {
 public:
  L3gd20h(I2cBus& bus, DataReady& ready, const L3gd20hSettings& settings);
  ~L3gd20h() override;

  // Identifies, resets and configures the chip. Throws DriverError (wrong chip, reset that
  // does not complete, configuration that does not read back) or I2cError.
  void start();
  // Waits for samples and returns them; recovers from faults by itself. Returns 0 only once
  // the stop flag is set; throws DriverError when no sample came for give_up_s while every
  // recovery failed (a dead sensor).
  std::size_t read(std::span<core::Sample> out) override;
  void close() override;  // powers the chip down (best effort)
  std::string describe() const override;
  core::SourceHealth health() const override;
  std::string counters_text() const override;
  double nominal_rate_hz() const override { return settings_.rate_hz; }

  void set_stop_flag(const std::atomic<bool>* stop) { stop_ = stop; }
  // Where warnings go (priority as syslog's, a key grouping repeats, the text); stderr by default.
  using Logger = std::function<void(int priority, const std::string& key, const std::string& text)>;
  void set_logger(Logger logger) { logger_ = std::move(logger); }
  const DriverCounters& counters() const { return counters_; }
  double rate_hz() const { return clock_.rate_hz(); }
  double sensitivity_dps() const;
  const L3gd20hSettings& settings() const { return settings_; }

 private:
  template <typename F>
  void transact(F&& f);
  std::uint8_t read_register(std::uint8_t reg);
  void read_registers(std::uint8_t reg, std::span<std::uint8_t> out);
  void write_register(std::uint8_t reg, std::uint8_t value);
  void configure();
  bool registers_intact();
  void housekeeping();
  void drain(std::optional<std::int64_t> edge_ns);
  void decode(std::span<const std::uint8_t> bytes, std::size_t count, bool stream_may_repeat);
  void recover(const std::string& why);

  I2cBus& bus_;
  DataReady& ready_;
  L3gd20hSettings settings_;
  SampleClock clock_;
  DriverCounters counters_;
  const std::atomic<bool>* stop_ = nullptr;
  Logger logger_;
  void warn(const std::string& key, const std::string& text);
  std::array<std::uint8_t, 5> expected_ctrl_{};  // CTRL1..CTRL5 as written
  std::uint8_t expected_fifo_ctrl_ = 0;
  std::uint8_t expected_low_odr_ = 0;
  std::int32_t sensitivity_1e5_ = 875;
  std::array<core::Sample, 2 * 32 + 8> pending_{};
  std::size_t pending_begin_ = 0, pending_end_ = 0;
  std::uint64_t next_index_ = 0;  // index of the next sample the FIFO will hand out
  std::int64_t last_drain_end_ns_ = 0;
  std::int64_t last_housekeeping_ns_ = 0;
  std::int64_t last_stamp_ns_ = 0;
  bool stream_drained_ = false;  // stream mode: the next burst starts with a repeat
  bool discard_next_ = false;    // DS: drop the first sample after a FIFO mode switch
  double temp_c_ = std::numeric_limits<double>::quiet_NaN();
  std::array<std::int16_t, 3> last_raw_{};
  std::uint64_t identical_run_ = 0;
  bool started_ = false;
  std::int64_t failing_since_ns_ = -1;  // first failed recovery since the last good sample
};

}  // namespace headingd::drivers
