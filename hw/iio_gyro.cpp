#include "hw/iio_gyro.hpp"

#include <fcntl.h>
#include <poll.h>
#include <syslog.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <numbers>

namespace headingd::drivers {
namespace {

constexpr int kPollMs = 100;       // every wait wakes this often to see the stop flag
constexpr double kSilenceS = 2.0;  // no scan this long (or 4 watermarks, if longer): the device is taken as gone
constexpr auto kRetryEvery = std::chrono::milliseconds(100);
constexpr std::size_t kScansPerRead = 64;
constexpr double kGapPeriods = 1.5;  // a timestamp step over 1.5 periods means scans were dropped
constexpr double kRadToDeg = 180.0 / std::numbers::pi;

}  // namespace

IioGyro::IioGyro(IioSettings settings) : settings_(std::move(settings)), binding_(bind_iio_device(settings_)) {
  try {
    open_node();
  } catch (...) {
    release_iio_device(binding_);
    throw;
  }
  restart_clock();
  last_data_ = Clock::now();
}

IioGyro::~IioGyro() { close(); }

void IioGyro::open_node() {
  fd_ = ::open(binding_.dev_node.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
  if (fd_ < 0) {
    const int error = errno;
    std::string why = "cannot open " + binding_.dev_node + ": " + std::strerror(error);
    if (error == EBUSY) why += " (another program has the buffer open)";
    if (error == EACCES || error == EPERM)
      why += " (the udev rule in config/99-headingd.rules gives group iio read access; add the user to it)";
    throw IioError(why);
  }
  bytes_.assign(binding_.layout.scan_bytes() * kScansPerRead, 0);
  have_ = 0;
}

void IioGyro::restart_clock() {
  base_ns_ = last_ns_ = -1;
  periods_ = 0;
  period_ns_ = binding_.sampling_frequency_hz > 0 ? 1e9 / binding_.sampling_frequency_hz : 0.0;
}

void IioGyro::close() {
  if (closed_) return;
  closed_ = true;
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
  if (!gone_) release_iio_device(binding_);
}

void IioGyro::warn(int priority, const std::string& key, const std::string& text) {
  if (logger_)
    logger_(priority, key, text);
  else
    std::fprintf(stderr, "headingd: %s\n", text.c_str());
}

void IioGyro::went_away(const std::string& why) {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
  release_iio_device(binding_);  // a device that is merely stuck gets its buffer restarted
  if (!gone_) {
    gone_ = true;
    gone_since_ = Clock::now();
    warn(LOG_WARNING, "iio gone", binding_.id + " (" + binding_.name + "): " + why + "; waiting for it to come back");
  }
  gone_why_ = why;
  last_attempt_ = Clock::now();
}

bool IioGyro::come_back() {
  const auto now = Clock::now();
  if (now - last_attempt_ < kRetryEvery) return false;
  last_attempt_ = now;
  try {
    IioBinding next = bind_iio_device(settings_);
    binding_ = std::move(next);
    open_node();
  } catch (const IioError& error) {
    if (fd_ >= 0) ::close(fd_), fd_ = -1;
    gone_why_ = error.what();
    if (settings_.give_up_s > 0 && now - gone_since_ > std::chrono::duration<double>(settings_.give_up_s))
      throw IioError("the IIO gyro has been gone for " + std::to_string(static_cast<int>(settings_.give_up_s)) +
                     " s: " + gone_why_);
    return false;
  }
  gone_ = false;
  ++counters_.recoveries;
  restart_clock();
  last_data_ = Clock::now();
  warn(LOG_NOTICE, "iio back", binding_.id + " (" + binding_.name + ") is back and set up again");
  return true;
}

void IioGyro::read_temperature(Clock::time_point now) {
  if (binding_.temperature_path.empty() || now - last_temperature_ < std::chrono::seconds(1)) return;
  last_temperature_ = now;
  const auto text = read_attribute(binding_.temperature_path);
  char* end = nullptr;
  const double value = text ? std::strtod(text->c_str(), &end) : std::nan("");
  if (!text || end == text->c_str() || !std::isfinite(value)) {
    // Some drivers refuse sysfs reads while the buffer runs: the rate goes on without a temperature.
    if (!temperature_failed_)
      warn(LOG_NOTICE, "iio temperature",
           "cannot read " + binding_.temperature_path + "; going on without temperature");
    temperature_failed_ = true;
    temp_c_ = std::nan("");
    return;
  }
  const bool raw = binding_.temperature_path.ends_with("_raw");
  temp_c_ = raw ? (value + binding_.temp_offset) * binding_.temp_scale / 1000.0 : value / 1000.0;
}

void IioGyro::add(std::int64_t t_ns, const Eigen::Vector3d& rate_dps) {
  if (last_ns_ >= 0) {
    const std::int64_t step = t_ns - last_ns_;
    if (step <= 0) {
      ++counters_.bad_stamps;
      return;
    }
    std::uint64_t periods = 1;
    if (period_ns_ > 0 && static_cast<double>(step) > kGapPeriods * period_ns_) {
      periods = static_cast<std::uint64_t>(std::llround(static_cast<double>(step) / period_ns_));
      counters_.lost_samples += periods - 1;
    }
    periods_ += periods;
    // Over a long baseline the kernel's stamps give the real rate (the datasheet's is +-15 %).
    if (periods_ >= 8) period_ns_ = static_cast<double>(t_ns - base_ns_) / static_cast<double>(periods_);
  } else {
    base_ns_ = t_ns;
  }
  last_ns_ = t_ns;
  core::Sample s;
  s.t_s = static_cast<double>(t_ns) / 1e9;  // correctly rounded: the same double a recording's 9 decimals parse to
  s.rate_dps = rate_dps;
  s.temp_c = temp_c_;
  pending_.push_back(s);
  ++counters_.samples;
}

void IioGyro::decode_scans() {
  const std::size_t scan = binding_.layout.scan_bytes();
  const auto& channels = binding_.layout.channels();
  std::size_t at = 0;
  for (; at + scan <= have_; at += scan) {
    const std::span<const std::uint8_t> bytes(bytes_.data() + at, scan);
    Eigen::Vector3d device;
    for (std::size_t axis = 0; axis < 3; ++axis) {
      const auto raw = static_cast<double>(iio::decode(channels[binding_.axes[axis]], bytes));
      const auto i = static_cast<Eigen::Index>(axis);
      device[i] = (raw + binding_.offset[i]) * binding_.scale[i];
    }
    add(iio::decode(channels[binding_.timestamp], bytes), binding_.mount * device * kRadToDeg);
  }
  if (at > 0 && at < have_) std::memmove(bytes_.data(), bytes_.data() + at, have_ - at);
  have_ -= at;
}

bool IioGyro::fill() {
  pollfd p{fd_, POLLIN, 0};
  const int ready = ::poll(&p, 1, kPollMs);
  if (ready < 0) {
    if (errno != EINTR) went_away(std::string("poll failed: ") + std::strerror(errno));
    return false;
  }
  if (ready == 0) {
    // A slow device with a deep watermark may be quiet for long between wake-ups: allow four of them.
    const double silence_s = std::max(kSilenceS, 4.0 * settings_.watermark * period_ns_ * 1e-9);
    if (Clock::now() - last_data_ > std::chrono::duration<double>(silence_s)) {
      char why[64];
      std::snprintf(why, sizeof why, "no scan for %.1f s", silence_s);
      went_away(why);
    }
    return false;
  }
  ++counters_.wakeups;
  const ssize_t n = ::read(fd_, bytes_.data() + have_, bytes_.size() - have_);
  if (n > 0) {
    have_ += static_cast<std::size_t>(n);
    last_data_ = Clock::now();
    decode_scans();
    return true;
  }
  if (n < 0 && (errno == EAGAIN || errno == EINTR)) return false;
  if (n < 0) ++counters_.read_errors;
  went_away(n == 0 ? "its buffer was closed" : std::string("read failed: ") + std::strerror(errno));
  return false;
}

std::size_t IioGyro::read(std::span<core::Sample> out) {
  while (pending_begin_ >= pending_.size()) {
    if (closed_ || (stop_ != nullptr && stop_->load())) return 0;
    pending_.clear();
    pending_begin_ = 0;
    read_temperature(Clock::now());
    if (gone_) {
      if (!come_back()) {
        ::poll(nullptr, 0, static_cast<int>(kRetryEvery.count() / 4));
        continue;
      }
    }
    fill();
  }
  const std::size_t n = std::min(out.size(), pending_.size() - pending_begin_);
  std::copy_n(pending_.begin() + static_cast<long>(pending_begin_), n, out.begin());
  pending_begin_ += n;
  return n;
}

std::string IioGyro::describe() const {
  char rate[32];
  std::snprintf(rate, sizeof rate, "%.1f", rate_hz());
  return "IIO gyro " + binding_.id + " (" + binding_.name + ") at " + rate + " Hz" +
         (binding_.trigger.empty() ? "" : ", trigger " + binding_.trigger);
}

core::SourceHealth IioGyro::health() const {
  core::SourceHealth h;
  h.live = true;
  h.rate_hz = rate_hz();
  h.samples = counters_.samples;
  h.lost_samples = counters_.lost_samples;
  h.bus_errors = counters_.read_errors;
  h.recoveries = counters_.recoveries;
  return h;
}

std::string IioGyro::counters_text() const {
  const auto& c = counters_;
  char text[256];
  std::snprintf(text, sizeof text,
                "samples=%llu lost=%llu read_errors=%llu recoveries=%llu bad_stamps=%llu wakeups=%llu",
                static_cast<unsigned long long>(c.samples), static_cast<unsigned long long>(c.lost_samples),
                static_cast<unsigned long long>(c.read_errors), static_cast<unsigned long long>(c.recoveries),
                static_cast<unsigned long long>(c.bad_stamps), static_cast<unsigned long long>(c.wakeups));
  return text;
}

std::string IioGyro::header_comment() const {
  const auto& b = binding_;
  char text[1024];
  std::snprintf(text, sizeof text,
                "# sensor: Linux IIO %s (%s) through %s\n"
                "# settings: sampling_frequency %g Hz, trigger %s, scan %s, scale %g %g %g rad/s per LSB, "
                "mount [%g %g %g; %g %g %g; %g %g %g]\n"
                "# recorded by: headingd (record, or run --record); time_s is the IIO buffer's monotonic timestamp\n",
                b.id.c_str(), b.name.c_str(), b.dev_node.c_str(), b.sampling_frequency_hz,
                b.trigger.empty() ? "(none)" : b.trigger.c_str(), b.layout.describe().c_str(), b.scale[0], b.scale[1],
                b.scale[2], b.mount(0, 0), b.mount(0, 1), b.mount(0, 2), b.mount(1, 0), b.mount(1, 1), b.mount(1, 2),
                b.mount(2, 0), b.mount(2, 1), b.mount(2, 2));
  return text;
}

}  // namespace headingd::drivers
