#pragma once
// An in-process L3GD20H at register level, standing in for the chip, its I2C bus and its
// DRDY/INT2 line on machines without hardware. It follows the datasheet (DS) as summarised in
// docs/l3gd20h.md: register defaults, WHO_AM_I, SUB bit-7 auto-increment with the 0x2D->0x28
// wrap, the 32-deep FIFO in bypass/stream/dynamic-stream with FSS/FTH/OVRN/EMPTY, the stream
// mode's repeated first sample after a drain, a self-clearing software reset, the INT2 level
// and its edges. Time is simulated: it moves with bus transactions, waits and sleeps.
#include <array>
#include <chrono>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "hw/data_ready.hpp"
#include "hw/i2c_bus.hpp"
#include "sim/gyro_simulator.hpp"

namespace headingd::drivers {

using RawSample = std::array<std::int16_t, 3>;

struct L3gd20hSimSettings {
  std::uint8_t address = 0x6B;
  double rate_error = 0.0;               // actual ODR = typical ODR * (1 + rate_error); DS: +-15 %
  double bus_hz = 400000.0;              // I2C clock, for the time a transaction takes
  std::int64_t irq_latency_ns = 40000;   // edge time stamp to the waiting thread waking
  std::int64_t reset_time_ns = 5000000;  // SW_RES self-clears after this
  double temp_c = 30.0;                  // die temperature when no scenario drives it
  std::uint8_t who_am_i = 0xD7;          // another part answers differently (L3GD20: 0xD4)
};

class L3gd20hSimulator final : public I2cBus, public DataReady {
 public:
  // Rates come from a GyroSimulator scenario (dps, quantised here per the full scale).
  L3gd20hSimulator(const L3gd20hSimSettings& settings, const std::string& scenario, std::uint64_t seed);
  // Rates come from a generator of raw samples by index (tests: counters, signs, patterns).
  L3gd20hSimulator(const L3gd20hSimSettings& settings, std::function<RawSample(std::uint64_t)> generator);

  // I2cBus
  void write_read(std::uint8_t address, std::span<const std::uint8_t> tx, std::span<std::uint8_t> rx) override;
  void write(std::uint8_t address, std::span<const std::uint8_t> tx) override;
  // DataReady
  std::optional<std::int64_t> wait(std::chrono::nanoseconds timeout) override;
  std::int64_t now_ns() const override { return clock_ns_; }
  void sleep(std::chrono::nanoseconds duration) override;
  bool has_edges() const override { return true; }
  std::string describe() const override { return "simulated L3GD20H"; }

  // Fault injection.
  void inject_nack(int transactions) { nack_ = transactions; }
  void inject_timeout(int transactions) { timeout_ = transactions; }
  void inject_stuck(std::int64_t duration_ns) { stuck_until_ns_ = clock_ns_ + duration_ns; }
  void inject_reset();                                                      // brown-out: registers back to defaults
  void inject_stall(std::int64_t duration_ns) { stall_ns_ = duration_ns; }  // the host is late once
  // From simulated time t_ns on, the chip stops answering for good (a dead sensor).
  void inject_dead_after(std::int64_t t_ns) { dead_after_ns_ = t_ns; }
  // At simulated time t_ns: `transactions` NACKs in a row; the output stuck for duration_ns.
  void inject_nack_at(std::int64_t t_ns, int transactions) {
    nack_at_ns_ = t_ns;
    nack_at_count_ = transactions;
  }
  void inject_stuck_at(std::int64_t t_ns, std::int64_t duration_ns) {
    stuck_at_ns_ = t_ns;
    stuck_at_duration_ns_ = duration_ns;
  }
  // Waits and sleeps also take real time, so a process using the simulator runs at the chip's pace.
  void set_realtime(bool realtime) { realtime_ = realtime; }
  // Real time: the steady-clock instant of simulated time 0 (set at the first pace), so a sample's
  // physical instant is this plus its simulated time.
  std::optional<std::chrono::steady_clock::time_point> wall_anchor() const { return wall_anchor_; }

  // What happened, for tests.
  struct Write {
    std::uint8_t reg;
    std::uint8_t value;
  };
  const std::vector<Write>& writes() const { return writes_; }
  std::uint64_t produced() const { return produced_; }
  std::uint64_t overwritten() const { return overwritten_; }
  std::uint64_t reserved_writes() const { return reserved_writes_; }
  double actual_rate_hz() const;
  std::uint8_t reg(std::uint8_t address) const { return regs_[address]; }
  // The index of the sample at the FIFO's head (the next to be read), for tests.
  std::optional<std::uint64_t> head_index() const;
  // True heading (deg) of the scenario at the latest produced sample.
  double truth_heading_deg() const { return truth_.heading_deg; }

 private:
  struct Stored {
    RawSample raw;
    std::uint64_t index;
  };
  void reset_registers();
  void advance_to(std::int64_t t_ns);
  void produce();
  void bus_time(std::size_t bytes);
  void check_faults();
  std::uint8_t read_register(std::uint8_t address);
  void write_register(std::uint8_t address, std::uint8_t value);
  bool fifo_enabled() const;
  std::uint8_t fifo_mode() const;
  std::uint8_t fifo_src() const;
  bool int2_active() const;
  std::int64_t period_ns() const;
  bool powered() const;
  RawSample next_raw();

  L3gd20hSimSettings settings_;
  std::unique_ptr<GyroSimulator> gyro_;
  std::function<RawSample(std::uint64_t)> generator_;
  TruthPoint truth_;
  std::array<std::uint8_t, 256> regs_{};
  std::deque<Stored> fifo_;
  Stored latch_{};  // the sample being read out of OUT_X_L..OUT_Z_H
  Stored last_read_{};
  bool repeat_last_ = false;  // stream mode: the first read after a drain repeats the last sample
  bool int2_level_ = false;
  std::int64_t clock_ns_ = 0;
  std::int64_t next_sample_ns_ = 0;
  std::int64_t reset_done_ns_ = -1;
  std::uint64_t produced_ = 0;
  std::uint64_t overwritten_ = 0;
  std::uint64_t reserved_writes_ = 0;
  std::vector<Write> writes_;
  int nack_ = 0;
  int timeout_ = 0;
  std::int64_t stuck_until_ns_ = -1;
  std::int64_t nack_at_ns_ = -1, stuck_at_ns_ = -1, stuck_at_duration_ns_ = 0;
  int nack_at_count_ = 0;
  RawSample stuck_value_{};
  std::int64_t stall_ns_ = 0;
  bool i2c_disabled_ = false;
  std::int64_t dead_after_ns_ = -1;
  bool realtime_ = false;
  std::optional<std::chrono::steady_clock::time_point> wall_anchor_;  // wall time of simulated 0
  // Sleeps until the wall clock has caught up with the simulated clock (realtime only).
  void pace();
  std::optional<std::int64_t> pending_edge_ns_;
};

}  // namespace headingd::drivers
