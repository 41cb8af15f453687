#include "sim/l3gd20h_sim.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <stdexcept>
#include <thread>

#include "hw/l3gd20h_registers.hpp"

namespace headingd::drivers {

using namespace l3gd20h;

namespace {
constexpr std::int64_t kTransactionOverheadNs = 50000;  // start, address, stop and host overhead

// The output rate divides by 1 + rate_error: at -1 or below no sample ever comes.
const L3gd20hSimSettings& checked(const L3gd20hSimSettings& settings) {
  if (!(std::abs(settings.rate_error) < 1.0))
    throw std::invalid_argument("simulated L3GD20H: rate_error must lie within -1..1 (exclusive)");
  return settings;
}
}  // namespace

L3gd20hSimulator::L3gd20hSimulator(const L3gd20hSimSettings& settings, const std::string& scenario, std::uint64_t seed)
    : settings_(checked(settings)) {
  auto built = build_scenario(scenario, seed, 0.0);
  if (!built) throw std::invalid_argument("unknown scenario '" + scenario + "'");
  // The chip quantises per its full scale, so the scenario's own quantisation is switched off,
  // and the scenario runs at the chip's real output rate.
  built->noise.quantum_dps = 1e-12;
  built->noise.full_scale_dps = 1e9;
  built->noise.rate_hz = 378.8 * (1.0 + settings_.rate_error);
  built->total_samples = ~std::uint64_t{0} >> 1;
  gyro_ = std::make_unique<GyroSimulator>(std::move(*built), seed);
  reset_registers();
}

L3gd20hSimulator::L3gd20hSimulator(const L3gd20hSimSettings& settings,
                                   std::function<RawSample(std::uint64_t)> generator)
    : settings_(checked(settings)), generator_(std::move(generator)) {
  reset_registers();
}

void L3gd20hSimulator::reset_registers() {
  regs_.fill(0);
  regs_[WHO_AM_I] = settings_.who_am_i;
  regs_[CTRL1] = 0x07;  // DS Table 17 default: power-down, axes enabled
  fifo_.clear();
  repeat_last_ = false;
  int2_level_ = false;
}

void L3gd20hSimulator::inject_reset() {
  advance_to(clock_ns_);
  reset_registers();
}

double L3gd20hSimulator::actual_rate_hz() const { return 1e9 / static_cast<double>(period_ns()); }

std::int64_t L3gd20hSimulator::period_ns() const {
  double typical_hz = 378.8;
  if (regs_[LOW_ODR] & kLowOdrLowRate) {
    constexpr double kLow[4] = {11.9, 23.7, 47.3, 47.3};
    typical_hz = kLow[regs_[CTRL1] >> 6];
  } else {
    for (const auto& rate : kRates)
      if ((regs_[CTRL1] & 0xC0) == rate.dr_bits) typical_hz = rate.typical_hz;
  }
  return std::llround(1e9 / (typical_hz * (1.0 + settings_.rate_error)));
}

bool L3gd20hSimulator::powered() const { return (regs_[CTRL1] & kCtrl1PowerOn) && (regs_[CTRL1] & kCtrl1AllAxes); }
bool L3gd20hSimulator::fifo_enabled() const { return regs_[CTRL5] & kCtrl5FifoEnable; }
std::uint8_t L3gd20hSimulator::fifo_mode() const {
  return fifo_enabled() ? regs_[FIFO_CTRL] & kFifoModeMask : kFifoBypass;
}

std::optional<std::uint64_t> L3gd20hSimulator::head_index() const {
  if (fifo_.empty()) return std::nullopt;
  return fifo_.front().index;
}

std::uint8_t L3gd20hSimulator::fifo_src() const {
  const auto size = static_cast<int>(fifo_.size());
  const std::uint8_t mode = fifo_mode();
  if (mode == kFifoBypass) return size == 0 ? kFifoSrcEmpty : 0;
  std::uint8_t src = 0;
  int fss = 0;
  if (size == 0) {
    src |= kFifoSrcEmpty;
  } else {
    // Dynamic stream: FSS + 1 unread samples (DS 4.2.5); otherwise FSS unread, capped at 31.
    fss = mode == kFifoDynamicStream ? size - 1 : std::min(size, 31);
  }
  if (size == kFifoDepth) src |= kFifoSrcOverrun;
  if (size > 0 && fss >= (regs_[FIFO_CTRL] & kFifoThresholdMask)) src |= kFifoSrcFth;
  return static_cast<std::uint8_t>(src | fss);
}

bool L3gd20hSimulator::int2_active() const {
  const std::uint8_t ctrl3 = regs_[CTRL3];
  const std::uint8_t src = fifo_src();
  return ((ctrl3 & kCtrl3Int2Fifo) && (src & kFifoSrcFth)) ||
         ((ctrl3 & kCtrl3Int2Overrun) && (src & kFifoSrcOverrun)) || ((ctrl3 & 0x01) && (src & kFifoSrcEmpty)) ||
         ((ctrl3 & 0x08) && !fifo_.empty());
}

RawSample L3gd20hSimulator::next_raw() {
  const std::uint64_t index = produced_;
  if (stuck_until_ns_ >= 0 && next_sample_ns_ <= stuck_until_ns_) {
    if (gyro_) {
      core::Sample ignored;
      gyro_->step(ignored, truth_);  // the world goes on; the chip's output does not
    }
    return stuck_value_;
  }
  RawSample raw{};
  if (generator_) {
    raw = generator_(index);
  } else {
    core::Sample sample;
    gyro_->step(sample, truth_);
    double sensitivity_dps = 0.00875;
    for (const auto& scale : kScales)
      if ((regs_[CTRL4] & 0x30) == scale.fs_bits || ((regs_[CTRL4] & 0x30) == 0x30 && scale.fs_bits == 0x20))
        sensitivity_dps = scale.sensitivity_1e5_dps * 1e-5;
    for (int axis = 0; axis < 3; ++axis) {
      const double lsb = std::round(sample.rate_dps[axis] / sensitivity_dps);
      raw[static_cast<std::size_t>(axis)] = static_cast<std::int16_t>(std::clamp(lsb, -32768.0, 32767.0));
    }
    settings_.temp_c = sample.temp_c;
  }
  stuck_value_ = raw;
  return raw;
}

void L3gd20hSimulator::produce() {
  const bool before = int2_active();
  Stored stored{next_raw(), produced_};
  ++produced_;
  const std::uint8_t mode = fifo_mode();
  if (mode == kFifoStream || mode == kFifoDynamicStream) {
    if (fifo_.size() == kFifoDepth) {
      fifo_.pop_front();  // stream: the oldest sample is overwritten
      ++overwritten_;
    }
    fifo_.push_back(stored);
  } else if (mode == 0x20) {  // FIFO mode: stops when full
    if (fifo_.size() < kFifoDepth)
      fifo_.push_back(stored);
    else
      ++overwritten_;
  } else {  // bypass: the output registers hold the latest sample
    fifo_.clear();
    fifo_.push_back(stored);
  }
  if (!before && int2_active() && !pending_edge_ns_) pending_edge_ns_ = next_sample_ns_;
  int2_level_ = int2_active();
}

void L3gd20hSimulator::advance_to(std::int64_t t_ns) {
  while (powered() && next_sample_ns_ <= t_ns) {
    clock_ns_ = std::max(clock_ns_, next_sample_ns_);
    produce();
    next_sample_ns_ += period_ns();
  }
  clock_ns_ = std::max(clock_ns_, t_ns);
  if (reset_done_ns_ >= 0 && clock_ns_ >= reset_done_ns_) {
    regs_[LOW_ODR] = static_cast<std::uint8_t>(regs_[LOW_ODR] & ~kLowOdrSoftwareReset);
    reset_done_ns_ = -1;
  }
}

void L3gd20hSimulator::bus_time(std::size_t bytes) {
  const double bits = 9.0 * static_cast<double>(bytes + 1);
  advance_to(clock_ns_ + kTransactionOverheadNs + std::llround(bits / settings_.bus_hz * 1e9));
}

void L3gd20hSimulator::pace() {
  if (!realtime_) return;
  // Against one anchor, so every simulated nanosecond counts, bus transactions included (pacing
  // only the waits ran 6 % fast: the bursts' bus time was never slept). Paced after every bus
  // transaction too, as an ioctl returns when the transfer ends: samples read in a burst reach
  // the caller no earlier than on the real bus.
  const auto now = std::chrono::steady_clock::now();
  if (!wall_anchor_) wall_anchor_ = now - std::chrono::nanoseconds(clock_ns_);
  std::this_thread::sleep_until(*wall_anchor_ + std::chrono::nanoseconds(clock_ns_));
}

void L3gd20hSimulator::check_faults() {
  if (nack_at_ns_ >= 0 && clock_ns_ >= nack_at_ns_) {
    nack_ = nack_at_count_;
    nack_at_ns_ = -1;
  }
  if (stuck_at_ns_ >= 0 && clock_ns_ >= stuck_at_ns_) {
    inject_stuck(stuck_at_duration_ns_);
    stuck_at_ns_ = -1;
  }
  if (dead_after_ns_ >= 0 && clock_ns_ >= dead_after_ns_) {
    advance_to(clock_ns_ + kTransactionOverheadNs);
    throw I2cError(I2cError::Kind::NoAck, EREMOTEIO, "simulated bus: Remote I/O error (sensor dead)");
  }
  if (timeout_ > 0) {
    --timeout_;
    advance_to(clock_ns_ + 25'000'000);  // the adapter gives up after its timeout
    throw I2cError(I2cError::Kind::BusTrouble, ETIMEDOUT, "simulated bus: Connection timed out");
  }
  if (nack_ > 0 || i2c_disabled_) {
    if (nack_ > 0) --nack_;
    advance_to(clock_ns_ + kTransactionOverheadNs);
    throw I2cError(I2cError::Kind::NoAck, EREMOTEIO, "simulated bus: Remote I/O error (no acknowledge)");
  }
}

std::uint8_t L3gd20hSimulator::read_register(std::uint8_t address) {
  switch (address) {
    case OUT_TEMP:
      return static_cast<std::uint8_t>(static_cast<std::int8_t>(std::lround(25.0 - settings_.temp_c)));
    case FIFO_SRC:
      return fifo_src();
    case STATUS:
      return fifo_.empty() ? 0 : 0x0F;
    case OUT_X_L: {
      const std::uint8_t mode = fifo_mode();
      if (mode == kFifoBypass) {
        if (!fifo_.empty()) latch_ = fifo_.back();
      } else if (repeat_last_ && !fifo_.empty()) {
        latch_ = last_read_;  // DS 4.2.3: after a drain the first read repeats the last one
        repeat_last_ = false;
      } else if (!fifo_.empty()) {
        latch_ = fifo_.front();
        fifo_.pop_front();
        last_read_ = latch_;
        if (fifo_.empty() && mode == kFifoStream) repeat_last_ = true;
      } else {
        latch_ = last_read_;  // nothing new: the port keeps the old value
      }
      int2_level_ = int2_active();
      [[fallthrough]];
    }
    case 0x29:
    case 0x2A:
    case 0x2B:
    case 0x2C:
    case OUT_Z_H: {
      const int axis = (address - OUT_X_L) / 2;
      const bool high = ((address - OUT_X_L) % 2) == 1;
      const bool big_endian = regs_[CTRL4] & 0x40;
      const auto value = static_cast<std::uint16_t>(latch_.raw[static_cast<std::size_t>(axis)]);
      return static_cast<std::uint8_t>((high != big_endian) ? value >> 8 : value & 0xFF);
    }
    default:
      return regs_[address];
  }
}

void L3gd20hSimulator::write_register(std::uint8_t address, std::uint8_t value) {
  writes_.push_back({address, value});
  if (address < 0x20 || (address > LOW_ODR)) {
    ++reserved_writes_;  // DS: writing reserved registers may damage the device
    return;
  }
  if (address == OUT_TEMP || address == STATUS || (address >= OUT_X_L && address <= OUT_Z_H) || address == FIFO_SRC ||
      address == 0x31)
    return;  // read-only
  const bool was_powered = powered();
  const std::uint8_t old_mode = fifo_mode();
  if (address == LOW_ODR) {
    if (value & 0x12) ++reserved_writes_;  // bits 4 and 1 must be written 0
    if (value & 0x08) i2c_disabled_ = true;
    if (value & kLowOdrSoftwareReset) {
      reset_registers();
      regs_[LOW_ODR] = kLowOdrSoftwareReset;
      reset_done_ns_ = clock_ns_ + settings_.reset_time_ns;
      return;
    }
  }
  regs_[address] = value;
  if (!was_powered && powered()) next_sample_ns_ = clock_ns_ + period_ns();
  if (fifo_mode() != old_mode && fifo_mode() == kFifoBypass) {
    fifo_.clear();  // DS 4.2.1: bypass resets the FIFO
    repeat_last_ = false;
  }
  int2_level_ = int2_active();
}

void L3gd20hSimulator::write_read(std::uint8_t address, std::span<const std::uint8_t> tx, std::span<std::uint8_t> rx) {
  check_faults();
  bus_time(tx.size());
  if (address != settings_.address)
    throw I2cError(I2cError::Kind::NoAck, ENXIO, "simulated bus: no device at this address");
  if (tx.empty()) return;
  const bool increment = tx[0] & kAutoIncrement;
  auto reg = static_cast<std::uint8_t>(tx[0] & 0x7F);
  const auto byte_ns = std::llround(9.0 / settings_.bus_hz * 1e9);
  for (auto& byte : rx) {
    // Bytes are clocked out one after another while the chip keeps sampling.
    advance_to(clock_ns_ + byte_ns);
    byte = read_register(reg);
    if (increment)
      reg =
          (reg == OUT_Z_H && fifo_enabled()) ? static_cast<std::uint8_t>(OUT_X_L) : static_cast<std::uint8_t>(reg + 1);
  }
  pace();  // as an ioctl returns: once the last byte is on the wire
}

void L3gd20hSimulator::write(std::uint8_t address, std::span<const std::uint8_t> tx) {
  check_faults();
  bus_time(tx.size());
  if (address != settings_.address)
    throw I2cError(I2cError::Kind::NoAck, ENXIO, "simulated bus: no device at this address");
  if (tx.empty()) return;
  const bool increment = tx[0] & kAutoIncrement;
  auto reg = static_cast<std::uint8_t>(tx[0] & 0x7F);
  for (std::size_t i = 1; i < tx.size(); ++i) {
    write_register(reg, tx[i]);
    if (increment) ++reg;
  }
  pace();
}

std::optional<std::int64_t> L3gd20hSimulator::wait(std::chrono::nanoseconds timeout) {
  struct Pace {
    L3gd20hSimulator& sim;
    ~Pace() { sim.pace(); }
  } pace_on_exit{*this};
  if (stall_ns_ > 0) {
    advance_to(clock_ns_ + stall_ns_);
    stall_ns_ = 0;
  }
  const std::int64_t deadline = clock_ns_ + timeout.count();
  while (!pending_edge_ns_) {
    const std::int64_t next = powered() ? std::min(next_sample_ns_, deadline) : deadline;
    advance_to(next);
    if (next >= deadline) break;
  }
  if (!pending_edge_ns_) return std::nullopt;
  const std::int64_t edge = *pending_edge_ns_;
  pending_edge_ns_.reset();
  advance_to(std::max(clock_ns_, edge + settings_.irq_latency_ns));
  return edge;
}

void L3gd20hSimulator::sleep(std::chrono::nanoseconds duration) {
  advance_to(clock_ns_ + duration.count());
  pace();
}

}  // namespace headingd::drivers
