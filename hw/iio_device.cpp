#include "hw/iio_device.hpp"

#include <dirent.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <sstream>

namespace headingd::drivers {
namespace {

constexpr const char* kUdevHint =
    "give the service's group access with the udev rule headingd installs (config/99-headingd.rules: group iio "
    "on /dev/iio:device* and the device's sysfs attributes), or run as root";

// A read-only /sys is no permission problem: under systemd it is the unit's ProtectKernelTunables=,
// which the packaged drop-in turns off for an IIO gyro (found under a real systemd: service.systemd_boot).
constexpr const char* kReadOnlyHint =
    "/sys is read-only here: under systemd, install the drop-in /usr/share/headingd/headingd-iio.conf as "
    "/etc/systemd/system/headingd.service.d/iio.conf and run systemctl daemon-reload";

// "<root>/sys/...", with no doubled slash for the usual root "/".
std::string under(const std::string& root, const std::string& path) {
  return (!root.empty() && root.back() == '/' ? root.substr(0, root.size() - 1) : root) + path;
}

bool exists(const std::string& path) {
  struct stat info {};
  return ::stat(path.c_str(), &info) == 0;
}

std::vector<std::string> entries(const std::string& dir) {
  std::vector<std::string> names;
  DIR* d = ::opendir(dir.c_str());
  if (d == nullptr) return names;
  while (const dirent* e = ::readdir(d)) {
    const std::string name = e->d_name;
    if (name != "." && name != "..") names.push_back(name);
  }
  ::closedir(d);
  std::sort(names.begin(), names.end());
  return names;
}

std::string joined(const std::vector<std::string>& names) {
  std::string text;
  for (const auto& n : names) text += (text.empty() ? "" : ", ") + n;
  return text.empty() ? "none" : text;
}

void write_attribute(const std::string& path, const std::string& value) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_TRUNC | O_CLOEXEC | O_NOCTTY);
  if (fd < 0) {
    const int error = errno;
    if (error == EROFS)
      throw IioReadOnlyError("cannot write " + path + ": " + std::strerror(error) + "; " + kReadOnlyHint);
    if (error == EACCES || error == EPERM)
      throw IioError("cannot write " + path + ": " + std::strerror(error) + "; " + kUdevHint);
    throw IioError("cannot open " + path + " for writing: " + std::strerror(error));
  }
  const std::string line = value + "\n";
  const ssize_t n = ::write(fd, line.data(), line.size());
  const int error = errno;
  ::close(fd);
  if (n != static_cast<ssize_t>(line.size())) {
    if (error == EBUSY)
      throw IioError("cannot write '" + value + "' to " + path +
                     ": device busy (its buffer is in use by another consumer)");
    throw IioError("cannot write '" + value + "' to " + path + ": " + std::strerror(error));
  }
}

std::string required(const std::string& path, const std::string& what) {
  const auto value = read_attribute(path);
  if (!value) throw IioError("cannot read " + path + " (" + what + "): " + std::strerror(errno));
  return *value;
}

double number_of(const std::string& text, const std::string& path) {
  char* end = nullptr;
  errno = 0;
  const double value = std::strtod(text.c_str(), &end);
  if (end == text.c_str() || *end != '\0' || errno != 0 || !std::isfinite(value))
    throw IioError(path + " holds '" + text + "', not a number");
  return value;
}

// The first of `names` that exists in `dir`, as a path; empty when none does.
std::string first_existing(const std::string& dir, std::initializer_list<const char*> names) {
  for (const char* n : names)
    if (exists(dir + "/" + n)) return dir + "/" + n;
  return {};
}

std::string describe_device(const std::string& dir) {
  const auto name = read_attribute(dir + "/name");
  return dir.substr(dir.rfind('/') + 1) + " (" + name.value_or("?") + ")";
}

iio::ScanChannel channel_of(const std::string& scan_dir, const std::string& name) {
  iio::ScanChannel channel;
  channel.name = name;
  const std::string index_path = scan_dir + "/" + name + "_index";
  channel.index = static_cast<unsigned>(number_of(required(index_path, "scan index"), index_path));
  const std::string type_path = scan_dir + "/" + name + "_type";
  std::string why;
  const auto type = iio::parse_channel_type(required(type_path, "scan type"), why);
  if (!type) throw IioError(type_path + " " + why);
  channel.type = *type;
  return channel;
}

// Axis values: one shared attribute (in_anglvel_scale) or one per axis (in_anglvel_x_scale).
Eigen::Vector3d per_axis(const std::string& dir, const char* what, std::optional<double> fallback) {
  Eigen::Vector3d v;
  const std::string shared = dir + "/in_anglvel_" + what;
  for (int axis = 0; axis < 3; ++axis) {
    const std::string own = dir + "/in_anglvel_" + "xyz"[axis] + "_" + what;
    std::string path = exists(own) ? own : shared;
    if (!exists(path)) {
      if (!fallback) throw IioError(describe_device(dir) + " has no " + shared + " (nor per-axis " + own + ")");
      v[axis] = *fallback;
      continue;
    }
    v[axis] = number_of(required(path, what), path);
  }
  return v;
}

double nearest_offered(const std::string& available_path, double wanted) {
  const auto text = read_attribute(available_path);
  if (!text) return wanted;  // nothing offered: try the value as given
  std::string list = *text;
  if (!list.empty() && list.front() == '[') {
    // A range "[min step max]": any value within it.
    std::replace(list.begin(), list.end(), '[', ' ');
    std::replace(list.begin(), list.end(), ']', ' ');
    std::istringstream in(list);
    double lo = 0, step = 0, hi = 0;
    in >> lo >> step >> hi;
    return std::clamp(wanted, lo, hi);
  }
  std::istringstream in(list);
  double best = 0.0, value = 0.0;
  bool any = false;
  while (in >> value)
    if (!any || std::abs(value - wanted) < std::abs(best - wanted)) best = value, any = true;
  if (!any) throw IioError(available_path + " offers no sampling frequency ('" + *text + "')");
  return best;
}

std::string pick_trigger(const IioSettings& settings, const std::string& devices, const std::string& dir,
                         const std::string& name) {
  std::vector<std::string> triggers;
  for (const auto& e : entries(devices))
    if (e.rfind("trigger", 0) == 0)
      if (const auto n = read_attribute(devices + "/" + e + "/name")) triggers.push_back(*n);
  const std::string current_path = dir + "/trigger/current_trigger";
  if (!settings.trigger.empty()) {
    if (std::find(triggers.begin(), triggers.end(), settings.trigger) == triggers.end())
      throw IioError("no IIO trigger named '" + settings.trigger + "' (have: " + joined(triggers) +
                     "); an hrtimer trigger is made with: mkdir /sys/kernel/config/iio/triggers/hrtimer/" +
                     settings.trigger);
    return settings.trigger;
  }
  if (const auto current = read_attribute(current_path); current && !current->empty()) return *current;
  // The device's own data-ready trigger is named after it ("l3gd20h-trigger", "bmi160-dev0").
  for (const auto& t : triggers)
    if (t.rfind(name, 0) == 0) return t;
  throw IioError(describe_device(dir) + " has no trigger set and none of its own (triggers: " + joined(triggers) +
                 "); make an hrtimer trigger (mkdir /sys/kernel/config/iio/triggers/hrtimer/headingd) and set "
                 "[sensor.iio] trigger = \"headingd\"");
}

}  // namespace

std::optional<std::string> read_attribute(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NOCTTY | O_NONBLOCK);
  if (fd < 0) return std::nullopt;
  char buffer[4096];
  const ssize_t n = ::read(fd, buffer, sizeof buffer - 1);
  const int error = errno;
  ::close(fd);
  if (n < 0) {
    errno = error;
    return std::nullopt;
  }
  std::string text(buffer, static_cast<std::size_t>(n));
  while (!text.empty() && (text.back() == '\n' || text.back() == '\0' || text.back() == ' ')) text.pop_back();
  return text;
}

std::optional<Eigen::Matrix3d> parse_mount_matrix(const std::string& text) {
  std::string cleaned = text;
  std::replace(cleaned.begin(), cleaned.end(), ',', ' ');
  std::replace(cleaned.begin(), cleaned.end(), ';', ' ');
  std::istringstream in(cleaned);
  Eigen::Matrix3d m;
  for (int row = 0; row < 3; ++row)
    for (int col = 0; col < 3; ++col)
      if (!(in >> m(row, col)) || !std::isfinite(m(row, col))) return std::nullopt;
  std::string rest;
  if (in >> rest) return std::nullopt;
  return m;
}

std::string find_iio_device(const IioSettings& settings) {
  const std::string devices = under(settings.root, "/sys/bus/iio/devices");
  std::vector<std::string> seen, candidates;
  for (const auto& e : entries(devices)) {
    if (e.rfind("iio:device", 0) != 0) continue;
    const std::string dir = devices + "/" + e;
    const std::string name = read_attribute(dir + "/name").value_or("");
    seen.push_back(e + " (" + name + ")");
    const auto& want = settings.device;
    if (want.empty()) {
      if (exists(dir + "/in_anglvel_scale") || exists(dir + "/in_anglvel_x_scale") || exists(dir + "/in_anglvel_x_raw"))
        candidates.push_back(dir);
      continue;
    }
    bool match = e == want || name == want;
    if (!match && want.find(',') != std::string::npos) {
      // of_node/compatible is a list of NUL-separated strings.
      const int fd = ::open((dir + "/of_node/compatible").c_str(), O_RDONLY | O_CLOEXEC);
      if (fd >= 0) {
        char buffer[1024];
        const ssize_t n = ::read(fd, buffer, sizeof buffer);
        ::close(fd);
        std::string all(buffer, static_cast<std::size_t>(std::max<ssize_t>(n, 0)));
        for (std::size_t at = 0; at < all.size();) {
          const std::size_t end = std::min(all.find('\0', at), all.size());
          if (all.compare(at, end - at, want) == 0) match = true;
          at = end + 1;
        }
      }
    }
    if (match) candidates.push_back(dir);
  }
  const std::string asked =
      settings.device.empty() ? "a gyro (angular-velocity channels)" : "'" + settings.device + "'";
  if (candidates.empty())
    throw IioError("no IIO device " + asked + " under " + devices + " (found: " + joined(seen) +
                   "); is the kernel driver loaded and the device described in the device tree?");
  if (candidates.size() > 1)
    throw IioError("more than one IIO device matches " + asked + " (found: " + joined(seen) +
                   "); name one in [sensor.iio] device");
  return candidates.front();
}

IioBinding bind_iio_device(const IioSettings& settings) {
  IioBinding b;
  b.sysfs_dir = find_iio_device(settings);
  b.id = b.sysfs_dir.substr(b.sysfs_dir.rfind('/') + 1);
  b.name = read_attribute(b.sysfs_dir + "/name").value_or(b.id);
  const std::string who = b.id + " (" + b.name + ")";
  b.dev_node = under(settings.root, "/dev/" + b.id);

  // Newer kernels (5.11+) put the scan elements and buffer controls in buffer0/; older ones use
  // scan_elements/ and buffer/.
  const bool buffer0 = exists(b.sysfs_dir + "/buffer0/in_anglvel_x_en");
  const std::string scan_dir = b.sysfs_dir + (buffer0 ? "/buffer0" : "/scan_elements");
  b.buffer_dir = b.sysfs_dir + (buffer0 ? "/buffer0" : "/buffer");
  if (!exists(b.buffer_dir + "/enable"))
    throw IioError(who + " has no buffer (" + b.buffer_dir + "/enable): its driver does not support buffered reads");
  if (required(b.buffer_dir + "/enable", "buffer state") == "1")
    throw IioError(who +
                   ": the buffer is already enabled by another consumer (iio-sensor-proxy, another headingd?); "
                   "stop it, or if none is running: echo 0 > " +
                   b.buffer_dir + "/enable");

  std::vector<std::string> enables;
  for (const auto& e : entries(scan_dir))
    if (e.size() > 3 && e.compare(e.size() - 3, 3, "_en") == 0) enables.push_back(e);
  const std::vector<std::string> wanted = {"in_anglvel_x", "in_anglvel_y", "in_anglvel_z", "in_timestamp"};
  for (const auto& w : wanted)
    if (std::find(enables.begin(), enables.end(), w + "_en") == enables.end())
      throw IioError(who + " has no buffered channel " + w + " (" + scan_dir + " offers: " + joined(enables) + ")");
  for (const auto& e : enables) {
    const std::string channel = e.substr(0, e.size() - 3);
    const bool on = std::find(wanted.begin(), wanted.end(), channel) != wanted.end();
    write_attribute(scan_dir + "/" + e, on ? "1" : "0");
  }
  std::vector<iio::ScanChannel> channels;
  channels.reserve(wanted.size());
  for (const auto& w : wanted) channels.push_back(channel_of(scan_dir, w));
  try {
    b.layout = iio::ScanLayout(std::move(channels));
  } catch (const std::invalid_argument& error) {
    throw IioError(who + ": " + error.what());
  }
  const auto position = [&](const std::string& name) {
    return static_cast<std::size_t>(b.layout.find(name) - b.layout.channels().data());
  };
  for (std::size_t axis = 0; axis < 3; ++axis) {
    b.axes[axis] = position(std::string("in_anglvel_") + "xyz"[axis]);
    if (b.layout.channels()[b.axes[axis]].type.repeat != 1)
      throw IioError(who + ": repeated angular-velocity elements are not supported");
  }
  b.timestamp = position("in_timestamp");
  if (b.layout.channels()[b.timestamp].type.storage_bits != 64)
    throw IioError(who + ": the timestamp channel is not 64 bits");

  b.scale = per_axis(b.sysfs_dir, "scale", std::nullopt);
  b.offset = per_axis(b.sysfs_dir, "offset", 0.0);
  if (settings.mount) {
    b.mount = *settings.mount;
  } else if (const auto path = first_existing(b.sysfs_dir, {"in_anglvel_mount_matrix", "mount_matrix"});
             !path.empty()) {
    const auto m = parse_mount_matrix(required(path, "mount matrix"));
    if (!m) throw IioError(path + " is not a 3x3 matrix 'x0, x1, x2; y0, y1, y2; z0, z1, z2'");
    b.mount = *m;
  }

  // Time stamps from the monotonic clock, the one headingd's samples are stamped with.
  if (const auto clock = b.sysfs_dir + "/current_timestamp_clock"; exists(clock)) {
    write_attribute(clock, "monotonic");
    if (required(clock, "timestamp clock") != "monotonic")
      throw IioError(clock + " does not take 'monotonic' (it reads " + *read_attribute(clock) + ")");
  }

  const std::string frequency = first_existing(b.sysfs_dir, {"in_anglvel_sampling_frequency", "sampling_frequency"});
  if (settings.sampling_frequency_hz > 0.0) {
    if (frequency.empty()) throw IioError(who + " has no sampling_frequency attribute to set");
    const double chosen = nearest_offered(frequency + "_available", settings.sampling_frequency_hz);
    char text[32];
    std::snprintf(text, sizeof text, "%g", chosen);
    write_attribute(frequency, text);
  }
  if (!frequency.empty()) b.sampling_frequency_hz = number_of(required(frequency, "sampling frequency"), frequency);

  if (exists(b.sysfs_dir + "/trigger/current_trigger")) {
    const std::string devices = under(settings.root, "/sys/bus/iio/devices");
    b.trigger = pick_trigger(settings, devices, b.sysfs_dir, b.name);
    // An hrtimer trigger has its own sampling_frequency: it must tick at the device's rate.
    for (const auto& e : entries(devices))
      if (e.rfind("trigger", 0) == 0 && read_attribute(devices + "/" + e + "/name") == b.trigger &&
          exists(devices + "/" + e + "/sampling_frequency") && b.sampling_frequency_hz > 0) {
        char text[32];
        std::snprintf(text, sizeof text, "%g", b.sampling_frequency_hz);
        write_attribute(devices + "/" + e + "/sampling_frequency", text);
      }
    write_attribute(b.sysfs_dir + "/trigger/current_trigger", b.trigger);
  }
  write_attribute(b.buffer_dir + "/length", std::to_string(settings.buffer_length));
  if (exists(b.buffer_dir + "/watermark"))
    write_attribute(b.buffer_dir + "/watermark", std::to_string(settings.watermark));

  if (const auto path = first_existing(b.sysfs_dir, {"in_temp_input"}); !path.empty()) {
    b.temperature_path = path;
  } else if (const auto raw = first_existing(b.sysfs_dir, {"in_temp_raw"}); !raw.empty()) {
    b.temperature_path = raw;
    if (const auto s = read_attribute(b.sysfs_dir + "/in_temp_scale")) b.temp_scale = number_of(*s, "in_temp_scale");
    if (const auto o = read_attribute(b.sysfs_dir + "/in_temp_offset")) b.temp_offset = number_of(*o, "in_temp_offset");
  }
  if (!exists(b.dev_node))
    throw IioError(who + ": no device node " + b.dev_node + " (is udev running, or /dev mounted in the sandbox?)");
  write_attribute(b.buffer_dir + "/enable", "1");
  return b;
}

void release_iio_device(const IioBinding& binding) {
  if (binding.buffer_dir.empty()) return;
  const int fd = ::open((binding.buffer_dir + "/enable").c_str(), O_WRONLY | O_TRUNC | O_CLOEXEC);
  if (fd < 0) return;
  [[maybe_unused]] const ssize_t n = ::write(fd, "0\n", 2);
  ::close(fd);
}

}  // namespace headingd::drivers
