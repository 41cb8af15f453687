#include "hw/l3gd20h.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>

#include "hw/l3gd20h_registers.hpp"
#include "hw/sensor_limits.hpp"

namespace headingd::drivers {

using namespace l3gd20h;
using std::chrono::milliseconds;

namespace {

constexpr std::int64_t kSoftwareResetTimeoutNs = 100'000'000;  // libdriver waits 12 ms; be generous
constexpr std::int64_t kTurnOnNs = 50'000'000;                 // DS Table 4: Ton 50 ms typical
constexpr double kTempOffsetC = 25.0;                          // DS 7.8 gives -1 LSB/degC and no offset: relative only
constexpr int kMaxDrainPasses = 8;

const RateSetting* find_rate(int hz) {
  for (const auto& r : kRates)
    if (r.nominal_hz == hz) return &r;
  return nullptr;
}
const ScaleSetting* find_scale(int dps) {
  for (const auto& s : kScales)
    if (s.full_scale_dps == dps) return &s;
  return nullptr;
}

std::string hex(unsigned value) {
  char text[8];
  std::snprintf(text, sizeof text, "0x%02X", value);
  return text;
}

}  // namespace

std::optional<std::string> validate(const L3gd20hSettings& s) {
  const auto check = [](const char* field, std::optional<std::string> problem) -> std::optional<std::string> {
    if (problem) return std::string(field) + " must be " + *problem;
    return std::nullopt;
  };
  for (auto problem : {check("address", address_not_allowed(s.address)), check("rate_hz", rate_not_allowed(s.rate_hz)),
                       check("bandwidth", bandwidth_not_allowed(s.bandwidth)),
                       check("full_scale_dps", full_scale_not_allowed(s.full_scale_dps)),
                       check("watermark", watermark_not_allowed(s.watermark))})
    if (problem) return problem;
  if (s.max_retries < 0 || s.max_retries > 100) return "max_retries must be 0..100";
  if (!(s.housekeeping_s > 0.0)) return "housekeeping_s must be positive";
  if (!(s.stuck_s > 0.0)) return "stuck_s must be positive";
  return std::nullopt;
}

L3gd20h::L3gd20h(I2cBus& bus, DataReady& ready, const L3gd20hSettings& settings)
    : bus_(bus),
      ready_(ready),
      settings_(settings),
      clock_(find_rate(settings.rate_hz) ? find_rate(settings.rate_hz)->typical_hz : 378.8) {
  if (const auto problem = validate(settings_)) throw DriverError("L3GD20H settings: " + *problem);
  sensitivity_1e5_ = find_scale(settings_.full_scale_dps)->sensitivity_1e5_dps;
}

L3gd20h::~L3gd20h() {
  try {
    close();
  } catch (...) {
    // Powering down is a courtesy; a dead bus must not stop the shutdown.
  }
}

double L3gd20h::sensitivity_dps() const { return sensitivity_1e5_ * 1e-5; }

core::SourceHealth L3gd20h::health() const {
  core::SourceHealth health;
  health.live = true;
  health.rate_hz = clock_.rate_hz();
  health.samples = counters_.samples;
  health.lost_samples = counters_.lost_samples;
  health.bus_errors = counters_.bus_errors;
  health.overruns = counters_.overruns;
  health.recoveries = counters_.recoveries;
  return health;
}

std::string L3gd20h::counters_text() const {
  const auto& c = counters_;
  char text[400];
  std::snprintf(text, sizeof text,
                "%.3f Hz measured; %llu samples, %llu lost in %llu overruns, %llu bus errors, %llu recoveries, %llu "
                "chip resets, %llu stuck, %llu wake-ups, %llu timeouts",
                clock_.rate_hz(), static_cast<unsigned long long>(c.samples),
                static_cast<unsigned long long>(c.lost_samples), static_cast<unsigned long long>(c.overruns),
                static_cast<unsigned long long>(c.bus_errors), static_cast<unsigned long long>(c.recoveries),
                static_cast<unsigned long long>(c.chip_resets), static_cast<unsigned long long>(c.stuck_events),
                static_cast<unsigned long long>(c.wakeups), static_cast<unsigned long long>(c.timeouts));
  return text;
}

std::string L3gd20h::describe() const {
  char text[160];
  std::snprintf(text, sizeof text, "L3GD20H at %s on %s, %d Hz nominal, +-%d dps, FIFO %s watermark %d",
                hex(settings_.address).c_str(), bus_.describe().c_str(), settings_.rate_hz, settings_.full_scale_dps,
                settings_.dynamic_stream ? "dynamic stream" : "stream", settings_.watermark);
  return text;
}

template <typename F>
void L3gd20h::transact(F&& f) {
  for (int attempt = 0;; ++attempt) {
    try {
      f();
      return;
    } catch (const I2cError& error) {
      ++counters_.bus_errors;
      if (!error.retryable() || attempt >= settings_.max_retries) throw;
      ready_.sleep(milliseconds(attempt + 1));  // back off a little more each time
    }
  }
}

std::uint8_t L3gd20h::read_register(std::uint8_t reg) {
  std::uint8_t value = 0;
  transact([&] {
    const std::uint8_t sub = reg;
    bus_.write_read(settings_.address, {&sub, 1}, {&value, 1});
  });
  return value;
}

void L3gd20h::read_registers(std::uint8_t reg, std::span<std::uint8_t> out) {
  transact([&] {
    const std::uint8_t sub = reg | kAutoIncrement;  // DS 5.1.1: bit 7 for multi-byte reads
    bus_.write_read(settings_.address, {&sub, 1}, out);
  });
}

void L3gd20h::write_register(std::uint8_t reg, std::uint8_t value) {
  transact([&] {
    const std::uint8_t bytes[2] = {reg, value};
    bus_.write(settings_.address, bytes);
  });
}

void L3gd20h::start() {
  const std::uint8_t who = read_register(WHO_AM_I);
  if (who != kWhoAmIValue) {
    throw DriverError(bus_.describe() + " address " + hex(settings_.address) + ": WHO_AM_I is " + hex(who) + ", not " +
                      hex(kWhoAmIValue) + " (is this an L3GD20H? L3GD20 answers 0xD4)");
  }
  // The chip keeps its registers across a host reboot: reset it rather than trust them.
  write_register(LOW_ODR, kLowOdrSoftwareReset);
  const std::int64_t deadline = ready_.now_ns() + kSoftwareResetTimeoutNs;
  while (read_register(LOW_ODR) & kLowOdrSoftwareReset) {
    if (ready_.now_ns() > deadline)
      throw DriverError(bus_.describe() + ": software reset did not complete within 100 ms");
    ready_.sleep(milliseconds(1));
  }
  if (read_register(WHO_AM_I) != kWhoAmIValue) throw DriverError(bus_.describe() + ": WHO_AM_I changed after reset");
  configure();
  started_ = true;
}

void L3gd20h::configure() {
  const RateSetting& rate = *find_rate(settings_.rate_hz);
  const ScaleSetting& scale = *find_scale(settings_.full_scale_dps);
  const std::uint8_t mode = settings_.dynamic_stream ? kFifoDynamicStream : kFifoStream;
  const auto ctrl1_on =
      static_cast<std::uint8_t>(rate.dr_bits | (settings_.bandwidth << 4) | kCtrl1PowerOn | kCtrl1AllAxes);
  expected_ctrl_ = {ctrl1_on, 0x00, kCtrl3Int2Fifo, static_cast<std::uint8_t>(kCtrl4Bdu | scale.fs_bits),
                    kCtrl5FifoEnable};
  expected_fifo_ctrl_ = static_cast<std::uint8_t>(mode | settings_.watermark);
  expected_low_odr_ = settings_.int2_active_low ? kLowOdrDrdyActiveLow : 0x00;

  // docs/l3gd20h.md section 5: configure in power-down, power on last.
  write_register(CTRL1, kCtrl1AllAxes);
  write_register(CTRL2, expected_ctrl_[1]);
  write_register(CTRL3, expected_ctrl_[2]);
  write_register(CTRL4, expected_ctrl_[3]);
  write_register(LOW_ODR, expected_low_odr_);
  write_register(FIFO_CTRL, kFifoBypass);
  write_register(CTRL5, expected_ctrl_[4]);
  write_register(FIFO_CTRL, expected_fifo_ctrl_);
  write_register(CTRL1, ctrl1_on);
  // Let the sensitivity settle (Ton), then restart the FIFO so it holds only good samples,
  // and drop the first one (DS 4.2: after a FIFO mode switch, discard the first sample).
  ready_.sleep(std::chrono::nanoseconds(kTurnOnNs));
  write_register(FIFO_CTRL, kFifoBypass);
  write_register(FIFO_CTRL, expected_fifo_ctrl_);
  if (!registers_intact()) throw DriverError(bus_.describe() + ": configuration did not read back");

  clock_.restart();
  next_index_ = 0;
  stream_drained_ = false;
  discard_next_ = true;
  identical_run_ = 0;
  last_drain_end_ns_ = ready_.now_ns();
  last_housekeeping_ns_ = ready_.now_ns();
  temp_c_ = kTempOffsetC - static_cast<std::int8_t>(read_register(OUT_TEMP));  // samples carry it from the first
}

bool L3gd20h::registers_intact() {
  std::array<std::uint8_t, 5> ctrl{};
  read_registers(CTRL1, ctrl);
  return ctrl == expected_ctrl_ && read_register(FIFO_CTRL) == expected_fifo_ctrl_ &&
         (read_register(LOW_ODR) & ~kLowOdrLowRate) == expected_low_odr_;
}

void L3gd20h::housekeeping() {
  const std::int64_t now = ready_.now_ns();
  if (now - last_housekeeping_ns_ < std::llround(settings_.housekeeping_s * 1e9)) return;
  last_housekeeping_ns_ = now;
  const auto raw = static_cast<std::int8_t>(read_register(OUT_TEMP));
  temp_c_ = kTempOffsetC - raw;
  if (!registers_intact()) {
    ++counters_.chip_resets;
    recover("registers lost their configuration (chip reset, brown-out?)");
  }
}

void L3gd20h::warn(const std::string& key, const std::string& text) {
  if (logger_)
    logger_(4, key, text);
  else
    std::fprintf(stderr, "<4>headingd: %s\n", text.c_str());
}

void L3gd20h::recover(const std::string& why) {
  ++counters_.recoveries;
  warn("L3GD20H recovery", "L3GD20H: " + why + "; setting the chip up again");
  start();
}

std::size_t L3gd20h::read(std::span<core::Sample> out) {
  if (out.empty()) return 0;
  while (pending_begin_ == pending_end_) {
    if (stop_ != nullptr && stop_->load()) return 0;
    try {
      if (!started_) start();
      housekeeping();
      const double watermark_s = (settings_.watermark + 1) / clock_.rate_hz();
      const auto timeout = std::chrono::nanoseconds(std::llround(std::max(0.02, 2.5 * watermark_s) * 1e9));
      const auto edge = ready_.wait(timeout);
      ++counters_.wakeups;
      if (!edge && ready_.has_edges()) ++counters_.timeouts;  // a missed edge or a silent chip: look anyway
      drain(edge);
    } catch (const std::exception& error) {
      // Bus trouble past its retries, a stuck or reset chip: count it, pause, set up again.
      ++counters_.recoveries;
      const std::int64_t now_ns = ready_.now_ns();
      if (failing_since_ns_ < 0) failing_since_ns_ = now_ns;
      const double failing_s = static_cast<double>(now_ns - failing_since_ns_) / 1e9;
      if (settings_.give_up_s > 0 && failing_s >= settings_.give_up_s) {
        throw DriverError("L3GD20H: no sample for " + std::to_string(static_cast<int>(failing_s)) +
                          " s, every recovery failed; last error: " + error.what());
      }
      warn("L3GD20H fault", std::string("L3GD20H: ") + error.what() + "; retrying");
      started_ = false;
      // Pause before setting up again, in slices, so a SIGTERM is seen within 10 ms.
      for (int slice = 0; slice < 10 && !(stop_ != nullptr && stop_->load()); ++slice) ready_.sleep(milliseconds(10));
    }
  }
  failing_since_ns_ = -1;
  const std::size_t n = std::min(out.size(), pending_end_ - pending_begin_);
  std::copy_n(pending_.begin() + static_cast<long>(pending_begin_), n, out.begin());
  pending_begin_ += n;
  if (pending_begin_ == pending_end_) pending_begin_ = pending_end_ = 0;
  return n;
}

void L3gd20h::drain(std::optional<std::int64_t> edge_ns) {
  const std::int64_t wake_ns = ready_.now_ns();
  std::array<std::uint8_t, std::size_t{6} * (kFifoDepth + 1)> bytes{};
  for (int pass = 0; pass < kMaxDrainPasses; ++pass) {
    const std::uint8_t src = read_register(FIFO_SRC);
    const std::int64_t src_ns = ready_.now_ns();
    if (src & kFifoSrcEmpty) break;
    const int fss = src & kFifoSrcCountMask;
    const bool overrun = src & kFifoSrcOverrun;
    // Dynamic stream holds FSS + 1 unread samples (DS 4.2.5); stream holds FSS, or 32 when
    // OVRN says it is full; after a drain, stream repeats the last sample first (DS 4.2.3).
    auto count = static_cast<std::size_t>(settings_.dynamic_stream ? fss + 1 : fss + (overrun ? 1 : 0));
    count = std::min<std::size_t>(count, kFifoDepth);
    // In stream mode a repeat may lead the burst whenever an earlier burst emptied the FIFO,
    // and FSS does not count it: read one more and drop the repeat if it is there.
    const bool repeat_possible = !settings_.dynamic_stream && stream_drained_;
    const std::size_t to_read = std::min<std::size_t>(count + (repeat_possible ? 1 : 0), kFifoDepth);
    read_registers(OUT_X_L, std::span(bytes).first(6 * to_read));  // one burst; 0x2D wraps to 0x28
    stream_drained_ = !settings_.dynamic_stream;                   // this burst read all FSS announced

    if (overrun) {
      // Samples were overwritten: how many, the clock tells (the newest sample is about now).
      ++counters_.overruns;
      if (clock_.anchored()) {
        // At the FIFO_SRC read the FIFO was full and its newest sample less than a period old.
        const double behind = static_cast<double>(src_ns - last_stamp_ns_) / clock_.period_ns();
        const auto lost = static_cast<std::int64_t>(std::floor(behind)) - static_cast<std::int64_t>(count);
        if (lost > 0) {
          next_index_ += static_cast<std::uint64_t>(lost);
          counters_.lost_samples += static_cast<std::uint64_t>(lost);
        }
      }
      clock_.anchor(next_index_ + count - 1, src_ns - std::llround(clock_.period_ns() / 2));
    } else if (pass == 0 && edge_ns && ready_.has_edges() && *edge_ns > last_drain_end_ns_) {
      // The watermark edge marks the sample that made the FIFO reach its threshold.
      const auto threshold = static_cast<std::uint64_t>(settings_.watermark);
      clock_.anchor(next_index_ + (settings_.dynamic_stream ? threshold : threshold - 1), *edge_ns);
    } else if (pass == 0 && !ready_.has_edges()) {
      clock_.anchor(next_index_ + count - 1, wake_ns);
    } else if (!clock_.anchored()) {
      clock_.anchor(next_index_ + count - 1, src_ns, /*provisional=*/true);
    }
    decode(std::span(bytes).first(6 * to_read), to_read, repeat_possible);
    // The watermark line falls once the level drops below the threshold and rises again when it
    // is reached: if fewer samples than that can have arrived since FIFO_SRC was read, another
    // look would find the FIFO below the watermark, and the next edge brings them. One bus
    // transfer fewer per wake-up; without edges, after an overrun or a timeout, look again.
    if (edge_ns && ready_.has_edges() && !overrun) {
      const double arrived = std::floor(static_cast<double>(ready_.now_ns() - src_ns) / clock_.period_ns()) + 1.0;
      if (arrived < settings_.watermark) break;
    }
  }
  last_drain_end_ns_ = ready_.now_ns();
}

void L3gd20h::decode(std::span<const std::uint8_t> bytes, std::size_t count, bool stream_may_repeat) {
  const auto stuck_limit = static_cast<std::uint64_t>(settings_.stuck_s * clock_.rate_hz());
  for (std::size_t i = 0; i < count; ++i) {
    std::array<std::int16_t, 3> raw{};
    for (std::size_t axis = 0; axis < 3; ++axis) {
      // Little-endian (CTRL4.BLE = 0), assembled with shifts so host byte order cannot matter.
      const auto low = bytes[6 * i + 2 * axis];
      const auto high = bytes[6 * i + 2 * axis + 1];
      raw[axis] = static_cast<std::int16_t>(static_cast<std::uint16_t>(low | (high << 8)));
    }
    // Stream mode: a burst after the FIFO ran empty starts with the last sample again
    // (DS 4.2.3). It is bit-identical to the one delivered before; drop it uncounted.
    if (i == 0 && stream_may_repeat && raw == last_raw_) continue;
    const std::uint64_t index = next_index_++;
    identical_run_ = raw == last_raw_ ? identical_run_ + 1 : 0;
    last_raw_ = raw;
    const std::int64_t t_ns = clock_.stamp(index);
    last_stamp_ns_ = t_ns;
    if (discard_next_) {
      discard_next_ = false;
      continue;
    }
    core::Sample& sample = pending_[pending_end_++];
    sample.t_s = static_cast<double>(t_ns) / 1e9;
    // An exact integer product over 1e5: the same double a recording's 5-decimal text parses to.
    for (std::size_t axis = 0; axis < 3; ++axis)
      sample.rate_dps[static_cast<Eigen::Index>(axis)] = static_cast<double>(raw[axis] * sensitivity_1e5_) / 1e5;
    sample.temp_c = temp_c_;
    ++counters_.samples;
  }
  if (identical_run_ >= stuck_limit) {
    ++counters_.stuck_events;
    identical_run_ = 0;
    throw DriverError("output stuck at the same value for " + std::to_string(settings_.stuck_s) + " s");
  }
}

void L3gd20h::close() {
  if (!started_) return;
  started_ = false;
  write_register(CTRL1, kCtrl1AllAxes);  // power-down
}

}  // namespace headingd::drivers
