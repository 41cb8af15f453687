#pragma once
// Any Linux IIO gyro (st_gyro, st_lsm6dsx, bmi160, bmg160, inv_mpu6050, inv_icm42600, adis16xxx
// ...) as a sample source: the kernel driver owns the chip, we read its buffer
// (/dev/iio:deviceN) with poll(), decode each scan with the channel descriptors, stamp it with
// the buffer's own monotonic timestamp, and measure the real rate online. Dropped scans show
// as gaps in the timestamps and are counted; a device that goes away (unbound, unplugged, its
// driver reloaded) is waited for and set up again, as the L3GD20H driver recovers after a reset.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "core/sample_source.hpp"
#include "hw/iio_device.hpp"

namespace headingd::drivers {

struct IioCounters {
  std::uint64_t samples = 0;       // delivered
  std::uint64_t lost_samples = 0;  // scans missing between two timestamps
  std::uint64_t read_errors = 0;
  std::uint64_t recoveries = 0;  // the device set up again after it went away
  std::uint64_t bad_stamps = 0;  // scans whose timestamp did not advance (dropped)
  std::uint64_t wakeups = 0;
};

class IioGyro final : public core::SampleSource {
 public:
  // Finds and sets up the device; throws IioError with what to do.
  explicit IioGyro(IioSettings settings);
  ~IioGyro() override;
  IioGyro(const IioGyro&) = delete;
  IioGyro& operator=(const IioGyro&) = delete;

  // Returns 0 only once the stop flag is set or after close(); throws IioError when the device
  // has been gone for give_up_s.
  std::size_t read(std::span<core::Sample> out) override;
  void close() override;
  std::string describe() const override;
  core::SourceHealth health() const override;
  std::string counters_text() const override;
  double nominal_rate_hz() const override { return binding_.sampling_frequency_hz; }

  void set_stop_flag(const std::atomic<bool>* stop) { stop_ = stop; }
  using Logger = std::function<void(int priority, const std::string& key, const std::string& text)>;
  void set_logger(Logger logger) { logger_ = std::move(logger); }
  const IioBinding& binding() const { return binding_; }
  const IioCounters& counters() const { return counters_; }
  double rate_hz() const { return period_ns_ > 0 ? 1e9 / period_ns_ : 0.0; }
  std::string header_comment() const;

 private:
  using Clock = std::chrono::steady_clock;
  void open_node();
  void went_away(const std::string& why);
  bool come_back();
  bool fill();  // one poll and read; false when nothing came
  void decode_scans();
  void add(std::int64_t t_ns, const Eigen::Vector3d& rate_dps);
  void read_temperature(Clock::time_point now);
  void warn(int priority, const std::string& key, const std::string& text);
  void restart_clock();

  IioSettings settings_;
  IioBinding binding_;
  int fd_ = -1;
  bool closed_ = false;
  bool gone_ = false;
  Clock::time_point gone_since_{}, last_data_{}, last_attempt_{}, last_temperature_{};
  std::string gone_why_;
  std::vector<std::uint8_t> bytes_;
  std::size_t have_ = 0;
  std::vector<core::Sample> pending_;
  std::size_t pending_begin_ = 0;
  IioCounters counters_;
  const std::atomic<bool>* stop_ = nullptr;
  Logger logger_;
  double temp_c_ = std::numeric_limits<double>::quiet_NaN();
  bool temperature_failed_ = false;
  // The rate over a long baseline: periods counted (with the lost ones) since base_ns_.
  std::int64_t base_ns_ = -1, last_ns_ = -1;
  std::uint64_t periods_ = 0;
  double period_ns_ = 0.0;
};

}  // namespace headingd::drivers
