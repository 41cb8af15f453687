#include "service/config_file.hpp"

#include <sys/stat.h>
#include <toml++/toml.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

#include "core/method.hpp"
#include "dds/server_address.hpp"
#include "hw/sensor_limits.hpp"
#include "service/log.hpp"

namespace headingd::app {
namespace {

std::string where(const std::string& file, const toml::node& node) {
  const auto& begin = node.source().begin;
  return file + ":" + std::to_string(begin.line) + ":" + std::to_string(begin.column);
}

[[noreturn]] void fail(const std::string& file, const toml::node& node, const std::string& key,
                       const std::string& problem) {
  throw ConfigError(where(file, node) + ": '" + key + "' " + problem);
}

std::string_view type_name(const toml::node& node) {
  switch (node.type()) {
    case toml::node_type::string:
      return "a string";
    case toml::node_type::integer:
      return "an integer";
    case toml::node_type::floating_point:
      return "a number";
    case toml::node_type::boolean:
      return "a boolean";
    case toml::node_type::array:
      return "an array";
    case toml::node_type::table:
      return "a table";
    default:
      return "a date/time";
  }
}

std::string shown(const toml::node& node) {
  std::ostringstream text;
  node.visit([&](const auto& value) { text << value; });
  return text.str();
}

double number_in(const std::string& file, const toml::node& node, const std::string& key, double lo, double hi,
                 bool lo_open) {
  std::optional<double> value;
  if (node.is_floating_point()) value = node.as_floating_point()->get();
  if (node.is_integer()) value = static_cast<double>(node.as_integer()->get());
  if (!value) fail(file, node, key, "must be a number, found " + std::string(type_name(node)) + " " + shown(node));
  const bool low_ok = lo_open ? *value > lo : *value >= lo;
  if (!std::isfinite(*value) || !low_ok || *value > hi) {
    std::ostringstream range;
    range << "is " << shown(node) << ", allowed " << (lo_open ? "(" : "[") << lo << ", " << hi << "]";
    fail(file, node, key, range.str());
  }
  return *value;
}

// Reads one TOML table key by key; every key must be claimed by a handler.
class TableReader {
 public:
  TableReader(const std::string& file, const toml::table& table, std::string prefix)
      : file_(file), table_(table), prefix_(std::move(prefix)) {}

  double number(const toml::node& node, const std::string& key, double lo, double hi, bool lo_open) const {
    return number_in(file_, node, key, lo, hi, lo_open);
  }
  core::Vec3 vector3(const toml::node& node, const std::string& key, double lo, double hi) const {
    const auto* array = node.as_array();
    if (array == nullptr || array->size() != 3)
      fail(file_, node, key, "must be an array of three numbers [x, y, z], found " + shown(node));
    core::Vec3 v;
    for (std::size_t axis = 0; axis < 3; ++axis)
      v[static_cast<Eigen::Index>(axis)] = number_in(file_, *array->get(axis), key, lo, hi, true);
    return v;
  }
  bool boolean(const toml::node& node, const std::string& key) const {
    if (!node.is_boolean()) fail(file_, node, key, "must be true or false, found " + shown(node));
    return node.as_boolean()->get();
  }
  std::uint32_t integer(const toml::node& node, const std::string& key, std::int64_t lo, std::int64_t hi) const {
    if (!node.is_integer()) fail(file_, node, key, "must be an integer, found " + shown(node));
    return static_cast<std::uint32_t>(
        number_in(file_, node, key, static_cast<double>(lo), static_cast<double>(hi), false));
  }

  // Calls handle(name, node, full_key) for each key; handle returns false for unknown keys.
  template <typename Handler>
  void each(Handler&& handle, const char* known) const {
    for (const auto& [raw_key, node] : table_) {
      const std::string name(raw_key.str());
      const std::string key = prefix_ + name;
      if (!handle(name, node, key)) fail(file_, node, key, std::string("is not a known key (known: ") + known + ")");
    }
  }
  const std::string& file() const { return file_; }

 private:
  const std::string& file_;
  const toml::table& table_;
  std::string prefix_;
};

const toml::table& as_table(const std::string& file, const toml::node& node, const std::string& key) {
  const auto* table = node.as_table();
  if (table == nullptr) fail(file, node, key, "must be a table ([" + key + "])");
  return *table;
}

void read_temperature(const TableReader& r, core::AutoSettings& a) {
  auto& t = a.temperature;
  r.each(
      [&](const std::string& name, const toml::node& node, const std::string& key) {
        if (name == "enabled")
          a.use_temperature = r.boolean(node, key);
        else if (name == "reference_c")
          t.reference_c = r.number(node, key, -60.0, 150.0, false);
        else if (name == "half_life_h")
          t.half_life_s = 3600.0 * r.number(node, key, 0.0, 24.0 * 365.0, true);
        else if (name == "min_span_c")
          t.min_span_c = r.number(node, key, 0.0, 100.0, true);
        else if (name == "quadratic_span_c")
          t.quadratic_span_c = r.number(node, key, 0.0, 1000.0, true);
        else if (name == "min_points")
          t.min_points = r.integer(node, key, 3, 100000);
        else if (name == "unmodelled_dps_per_c")
          a.unmodelled_bias_per_c_dps = r.number(node, key, 0.0, 1.0, false);
        else
          return false;
        return true;
      },
      "enabled, reference_c, half_life_h, min_span_c, quadratic_span_c, min_points, unmodelled_dps_per_c");
}

void read_auto(const TableReader& r, core::AutoSettings& a) {
  r.each(
      [&](const std::string& name, const toml::node& node, const std::string& key) {
        if (name == "min_segment_s")
          a.min_segment_s = r.number(node, key, 0.0, 600.0, true);
        else if (name == "k_range")
          a.k_range = r.number(node, key, 0.0, 1000.0, true);
        else if (name == "k_mean")
          a.k_mean = r.number(node, key, 0.0, 1000.0, true);
        else if (name == "k_mean_pooled")
          a.k_mean_pooled = r.number(node, key, 0.0, 1000.0, true);
        else if (name == "arw_dps_rt_hz")
          a.arw_dps_rt_hz = r.vector3(node, key, 0.0, 10.0);
        else if (name == "bias_walk_dps_rt_s")
          a.bias_walk_dps_rt_s = r.number(node, key, 0.0, 1.0, false);
        else if (name == "block_s")
          a.block_s = r.number(node, key, 0.0, 60.0, true);
        else if (name == "scale_factor_sigma")
          a.scale_factor_sigma = r.number(node, key, 0.0, 0.5, false);
        else if (name == "retract_before_creep")
          a.retract_before_creep = r.boolean(node, key);
        else if (name == "calibrate_sigma")
          a.calibrate_sigma = r.boolean(node, key);
        else if (name == "recover_after_s")
          a.recover_after_s = r.number(node, key, 0.0, 86400.0, false);
        else if (name == "zero_rate_sigma_dps")
          a.zero_rate_sigma_dps = r.number(node, key, 0.0, 100.0, true);
        else if (name == "restart_bias_sigma_dps")
          a.restart_bias_sigma_dps = r.number(node, key, 0.0, 10.0, false);
        else
          return false;
        return true;
      },
      "min_segment_s, k_range, k_mean, k_mean_pooled, arw_dps_rt_hz, bias_walk_dps_rt_s, block_s, "
      "scale_factor_sigma, calibrate_sigma, retract_before_creep, recover_after_s, zero_rate_sigma_dps, "
      "restart_bias_sigma_dps");
}

void read_estimator(const TableReader& r, core::EstimatorSettings& e) {
  core::BiasSettings& s = e.segments;
  r.each(
      [&](const std::string& name, const toml::node& node, const std::string& key) {
        if (name == "method") {
          const auto* text = node.as_string();
          const auto method = text ? core::parse_method(text->get()) : std::nullopt;
          if (!method) fail(r.file(), node, key, "is " + shown(node) + ", allowed \"auto\", \"a\", \"b\" or \"c\"");
          e.method = *method;
        } else if (name == "segment_s") {
          s.segment_s = r.number(node, key, 0.0, 600.0, true);
        } else if (name == "k_range") {
          s.k_range = r.number(node, key, 0.0, 1000.0, true);
        } else if (name == "k_mean") {
          s.k_mean = r.number(node, key, 0.0, 1000.0, true);
        } else if (name == "n_means") {
          s.n_means = r.integer(node, key, 1, static_cast<std::int64_t>(core::MeanHistory::kMaxMeans));
        } else if (name == "still_at_start") {
          s.still_at_start = r.boolean(node, key);
        } else if (name == "sigma_still_dps") {
          s.sigma_still_dps = r.vector3(node, key, 0.0, 100.0);
        } else if (name == "auto") {
          read_auto(TableReader(r.file(), as_table(r.file(), node, key), key + "."), e.automatic);
        } else if (name == "temperature") {
          read_temperature(TableReader(r.file(), as_table(r.file(), node, key), key + "."), e.automatic);
        } else {
          return false;
        }
        return true;
      },
      "method, segment_s, k_range, k_mean, n_means, sigma_still_dps, still_at_start, [estimator.auto], "
      "[estimator.temperature]");
}

std::string text_of(const std::string& file, const toml::node& node, const std::string& key) {
  const auto* text = node.as_string();
  if (text == nullptr) fail(file, node, key, "must be a string, found " + shown(node));
  return std::string(text->get());
}

// "IPV4:PORT" (server id 0) or a list of them, the position being the server id; "" skips one.
std::vector<std::string> server_list(const std::string& file, const toml::node& node, const std::string& key) {
  std::vector<std::string> servers;
  const auto check = [&](const toml::node& entry) {
    const std::string text = text_of(file, entry, key);
    std::string why;
    if (!text.empty() && !parse_server_address(text, why)) fail(file, entry, key, why + ", found " + shown(entry));
    servers.push_back(text);
  };
  if (const auto* array = node.as_array()) {
    for (const auto& entry : *array) check(entry);
  } else {
    check(node);
  }
  if (std::all_of(servers.begin(), servers.end(), [](const std::string& s) { return s.empty(); }))
    fail(file, node, key, "names no server, found " + shown(node));
  return servers;
}

void read_security(const TableReader& r, DdsSecurity& s) {
  r.each(
      [&](const std::string& name, const toml::node& node, const std::string& key) {
        if (name == "enabled")
          s.enabled = r.boolean(node, key);
        else if (name == "identity_ca")
          s.identity_ca = text_of(r.file(), node, key);
        else if (name == "certificate")
          s.certificate = text_of(r.file(), node, key);
        else if (name == "private_key")
          s.private_key = text_of(r.file(), node, key);
        else if (name == "permissions_ca")
          s.permissions_ca = text_of(r.file(), node, key);
        else if (name == "governance")
          s.governance = text_of(r.file(), node, key);
        else if (name == "permissions")
          s.permissions = text_of(r.file(), node, key);
        else
          return false;
        return true;
      },
      "enabled, identity_ca, certificate, private_key, permissions_ca, governance, permissions");
}

// ROS 2's name rules: tokens of letters, digits and underscores, not starting with a digit,
// separated by single slashes; no trailing slash. `absolute_only` for namespaces.
bool ros_name_ok(const std::string& name, bool absolute_only, bool allow_slash) {
  if (absolute_only && name == "/") return true;
  if (name.empty() || (absolute_only && name.front() != '/') || name.back() == '/') return false;
  if (!allow_slash && name.find('/') != std::string::npos) return false;
  bool token_start = true;
  for (std::size_t i = 0; i < name.size(); ++i) {
    const char c = name[i];
    if (c == '/') {
      if (i > 0 && name[i - 1] == '/') return false;
      token_start = true;
      continue;
    }
    const bool letter = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_';
    const bool digit = c >= '0' && c <= '9';
    if (!letter && !(digit && !token_start)) return false;
    token_start = false;
  }
  return true;
}

std::string ros_name(const TableReader& r, const toml::node& node, const std::string& key, bool absolute_only,
                     bool allow_slash, bool allow_empty) {
  std::string value = text_of(r.file(), node, key);
  if (allow_empty && value.empty()) return value;
  if (!ros_name_ok(value, absolute_only, allow_slash))
    fail(r.file(), node, key,
         "is " + shown(node) + ": not a valid ROS 2 name (letters, digits, '_' and " +
             (absolute_only ? "'/', starting with '/'"
              : allow_slash ? "'/' between tokens"
                            : "no '/'") +
             "; a token must not start with a digit)");
  return value;
}

void read_dds(const TableReader& r, DdsSettings& d) {
  r.each(
      [&](const std::string& name, const toml::node& node, const std::string& key) {
        if (name == "security") {
          read_security(TableReader(r.file(), as_table(r.file(), node, key), key + "."), d.security);
          return true;
        }
        if (name == "domain_id")
          d.domain_id = static_cast<int>(r.integer(node, key, 0, 232));
        else if (name == "prefix")
          d.prefix = text_of(r.file(), node, key);
        else if (name == "ros2_naming")
          d.ros2_naming = r.boolean(node, key);
        else if (name == "publish_imu")
          d.publish_imu = r.boolean(node, key);
        else if (name == "imu_topic")
          d.imu_topic = ros_name(r, node, key, false, true, false);
        else if (name == "frame_id")
          d.frame_id = text_of(r.file(), node, key);
        else if (name == "orientation_rate_hz")
          d.orientation_rate_hz = r.number(node, key, 0.0, 1000.0, true);
        else if (name == "orientation_reliable")
          d.orientation_reliable = r.boolean(node, key);
        else if (name == "orientation_deadline_periods")
          d.orientation_deadline_periods = r.number(node, key, 0.0, 1000.0, false);
        else if (name == "profiles_xml") {
          d.profiles_xml = text_of(r.file(), node, key);
          // Checked here, so a bad path is a configuration error (78) at start and on reload.
          struct stat info {};
          if (::stat(d.profiles_xml->c_str(), &info) != 0 || ::access(d.profiles_xml->c_str(), R_OK) != 0)
            fail(r.file(), node, key, "is " + shown(node) + ": cannot read it: " + std::strerror(errno));
          if (!S_ISREG(info.st_mode)) fail(r.file(), node, key, "is " + shown(node) + ": not a regular file");
        } else if (name == "on_duplicate") {
          const std::string value = text_of(r.file(), node, key);
          if (value == "warn")
            d.on_duplicate = DuplicatePolicy::Warn;
          else if (value == "refuse")
            d.on_duplicate = DuplicatePolicy::Refuse;
          else
            fail(r.file(), node, key, "is " + shown(node) + ", allowed \"warn\" or \"refuse\"");
        } else if (name == "transport") {
          const std::string value = text_of(r.file(), node, key);
          if (value == "udp")
            d.transport = DdsTransport::Udp;
          else if (value == "shm")
            d.transport = DdsTransport::SharedMemory;
          else
            fail(r.file(), node, key, "is " + shown(node) + ", allowed \"udp\" or \"shm\"");
        } else if (name == "discovery_server") {
          d.discovery_servers = server_list(r.file(), node, key);
        } else if (name == "command_max_age_s")
          d.command_limits.max_age_s = r.number(node, key, 0.0, 3600.0, true);
        else
          return false;
        return true;
      },
      "domain_id, prefix, ros2_naming, publish_imu, imu_topic, frame_id, orientation_rate_hz, orientation_reliable, "
      "orientation_deadline_periods, transport, on_duplicate, "
      "profiles_xml, discovery_server, command_max_age_s, [dds.security]");
}

// An integer setting of the sensor, checked against the chip's allowed values (hw/sensor_limits).
int sensor_value(const TableReader& r, const toml::node& node, const std::string& key,
                 std::optional<std::string> (*not_allowed)(long long)) {
  if (!node.is_integer()) fail(r.file(), node, key, "must be an integer, found " + shown(node));
  const std::int64_t value = node.as_integer()->get();
  if (const auto allowed = not_allowed(value)) fail(r.file(), node, key, "is " + shown(node) + ", allowed " + *allowed);
  return static_cast<int>(value);
}

void read_iio(const TableReader& r, drivers::IioSettings& s) {
  r.each(
      [&](const std::string& name, const toml::node& node, const std::string& key) {
        if (name == "device")
          s.device = text_of(r.file(), node, key);
        else if (name == "trigger")
          s.trigger = text_of(r.file(), node, key);
        else if (name == "sampling_frequency_hz")
          s.sampling_frequency_hz = r.number(node, key, 0.0, 100000.0, false);
        else if (name == "buffer_length")
          s.buffer_length = static_cast<int>(r.integer(node, key, 2, 65536));
        else if (name == "watermark")
          s.watermark = static_cast<int>(r.integer(node, key, 1, 65536));
        else if (name == "mount_matrix") {
          s.mount = drivers::parse_mount_matrix(text_of(r.file(), node, key));
          if (!s.mount)
            fail(r.file(), node, key, "is " + shown(node) + ", expected \"x0, x1, x2; y0, y1, y2; z0, z1, z2\"");
        } else if (name == "root")
          s.root = text_of(r.file(), node, key);
        else if (name == "give_up_s")
          s.give_up_s = r.number(node, key, 0.0, 86400.0, false);
        else
          return false;
        return true;
      },
      "device, trigger, sampling_frequency_hz, buffer_length, watermark, mount_matrix, root, give_up_s");
  if (s.watermark > s.buffer_length)
    throw ConfigError(r.file() + ": sensor.iio.watermark (" + std::to_string(s.watermark) +
                      ") must not exceed sensor.iio.buffer_length (" + std::to_string(s.buffer_length) + ")");
}

void read_sensor(const TableReader& r, SensorOptions& s) {
  r.each(
      [&](const std::string& name, const toml::node& node, const std::string& key) {
        if (name == "kind")  // checked against the registered sensors (app/sensor.cpp) when one is opened
          s.kind = text_of(r.file(), node, key);
        else if (name == "iio")
          read_iio(TableReader(r.file(), as_table(r.file(), node, key), key + "."), s.iio);
        else if (name == "bus")
          s.bus = text_of(r.file(), node, key);
        else if (name == "address")
          s.address = sensor_value(r, node, key, drivers::address_not_allowed);
        else if (name == "rate_hz")
          s.rate_hz = sensor_value(r, node, key, drivers::rate_not_allowed);
        else if (name == "bandwidth")
          s.bandwidth = sensor_value(r, node, key, drivers::bandwidth_not_allowed);
        else if (name == "full_scale_dps")
          s.full_scale_dps = sensor_value(r, node, key, drivers::full_scale_not_allowed);
        else if (name == "watermark")
          s.watermark = sensor_value(r, node, key, drivers::watermark_not_allowed);
        else if (name == "gpio_chip")
          s.gpio_chip = text_of(r.file(), node, key);
        else if (name == "gpio_line")
          s.gpio_line = r.integer(node, key, 0, 1023);
        else if (name == "int2_active_low")
          s.int2_active_low = r.boolean(node, key);
        else
          return false;
        return true;
      },
      "kind, bus, address, rate_hz, bandwidth, full_scale_dps, watermark, gpio_chip, gpio_line, int2_active_low, "
      "[sensor.iio]");
}

void read_state(const TableReader& r, Config& c) {
  r.each(
      [&](const std::string& name, const toml::node& node, const std::string& key) {
        if (name == "path")
          c.state_path = text_of(r.file(), node, key);
        else if (name == "save_interval_s")
          c.state_save_interval_s = r.number(node, key, 1.0, 86400.0, false);
        else if (name == "restore_heading")
          c.state_restore_heading = r.boolean(node, key);
        else
          return false;
        return true;
      },
      "path, save_interval_s, restore_heading");
}

void read_record(const TableReader& r, Config& c) {
  r.each(
      [&](const std::string& name, const toml::node& node, const std::string& key) {
        if (name == "dir")
          c.record_dir = text_of(r.file(), node, key);
        else if (name == "split_hours")
          c.record_split_hours = r.number(node, key, 0.001, 168.0, false);
        else if (name == "keep_hours")
          c.record_keep_hours = r.number(node, key, 0.0, 87600.0, false);
        else
          return false;
        return true;
      },
      "dir, split_hours, keep_hours");
}

void read_stop_hint(const TableReader& r, StopHintSettings& h) {
  r.each(
      [&](const std::string& name, const toml::node& node, const std::string& key) {
        if (name == "topic")
          h.topic = ros_name(r, node, key, false, true, true);
        else if (name == "type") {
          const std::string value = text_of(r.file(), node, key);
          if (value == "odometry")
            h.type = StopHintType::Odometry;
          else if (value == "twist")
            h.type = StopHintType::Twist;
          else if (value == "twist_stamped")
            h.type = StopHintType::TwistStamped;
          else
            fail(r.file(), node, key, "is " + shown(node) + ", allowed \"odometry\", \"twist\" or \"twist_stamped\"");
        } else if (name == "linear_stopped_m_s")
          h.linear_stopped_m_s = r.number(node, key, 0.0, 10.0, true);
        else if (name == "angular_stopped_rad_s")
          h.angular_stopped_rad_s = r.number(node, key, 0.0, 10.0, true);
        else if (name == "hold_s")
          h.hold_s = r.number(node, key, 0.0, 60.0, false);
        else if (name == "stale_s")
          h.stale_s = r.number(node, key, 0.0, 60.0, true);
        else
          return false;
        return true;
      },
      "topic, type, linear_stopped_m_s, angular_stopped_rad_s, hold_s, stale_s");
}

void read_ros(const TableReader& r, RosSettings& s) {
  r.each(
      [&](const std::string& name, const toml::node& node, const std::string& key) {
        if (name == "stop_hint") {
          read_stop_hint(TableReader(r.file(), as_table(r.file(), node, key), key + "."), s.stop_hint);
          return true;
        }
        if (name == "node_name")
          s.node_name = ros_name(r, node, key, false, false, false);
        else if (name == "namespace")
          s.node_namespace = ros_name(r, node, key, true, true, false);
        else if (name == "distro") {
          const std::string value = text_of(r.file(), node, key);
          if (value == "humble")
            s.distro = RosDistro::Humble;
          else if (value == "jazzy" || value == "iron" || value == "kilted" || value == "rolling")
            s.distro = RosDistro::Jazzy;
          else
            fail(r.file(), node, key,
                 "is " + shown(node) + ", allowed \"humble\", or \"iron\", \"jazzy\", \"kilted\", \"rolling\"");
        } else if (name == "discovery_info")
          s.discovery_info = r.boolean(node, key);
        else if (name == "imu_orientation") {
          const std::string value = text_of(r.file(), node, key);
          if (value == "yaw_only")
            s.imu_orientation = ImuOrientation::YawOnly;
          else if (value == "attitude")
            s.imu_orientation = ImuOrientation::Attitude;
          else
            fail(r.file(), node, key, "is " + shown(node) + ", allowed \"yaw_only\" or \"attitude\"");
        } else if (name == "orientation_stddev_rad")
          s.orientation_stddev_rad = r.number(node, key, 0.0, 10.0, true);
        else if (name == "angular_velocity_stddev_rad_s")
          s.angular_velocity_stddev_rad_s = r.number(node, key, 0.0, 10.0, true);
        else if (name == "diagnostics")
          s.diagnostics = r.boolean(node, key);
        else if (name == "temperature_topic")
          s.temperature_topic = ros_name(r, node, key, false, true, true);
        else if (name == "heading_sigma_warn_deg")
          s.heading_sigma_warn_deg = r.number(node, key, 0.0, 360.0, true);
        else if (name == "heading_sigma_error_deg")
          s.heading_sigma_error_deg = r.number(node, key, 0.0, 360.0, true);
        else if (name == "still_age_warn_s")
          s.still_age_warn_s = r.number(node, key, 0.0, 1e7, true);
        else if (name == "hardware_id")
          s.hardware_id = text_of(r.file(), node, key);
        else
          return false;
        return true;
      },
      "node_name, namespace, distro, discovery_info, imu_orientation, orientation_stddev_rad, "
      "angular_velocity_stddev_rad_s, diagnostics, temperature_topic, heading_sigma_warn_deg, heading_sigma_error_deg, "
      "still_age_warn_s, hardware_id, [ros.stop_hint]");
}

Config interpret(const toml::table& root, const std::string& file) {
  Config config;
  for (const auto& [raw_key, node] : root) {
    const std::string key(raw_key.str());
    if (key == "estimator") {
      read_estimator(TableReader(file, as_table(file, node, key), "estimator."), config.estimator);
    } else if (key == "dds") {
      read_dds(TableReader(file, as_table(file, node, key), "dds."), config.dds);
    } else if (key == "sensor") {
      read_sensor(TableReader(file, as_table(file, node, key), "sensor."), config.sensor);
    } else if (key == "log") {
      TableReader r(file, as_table(file, node, key), "log.");
      r.each(
          [&](const std::string& name, const toml::node& value, const std::string& full_key) {
            if (name != "level") return false;
            config.log_level = text_of(file, value, full_key);
            LogPriority level;
            if (!parse_log_level(config.log_level, level))
              fail(file, value, full_key,
                   "is " + shown(value) + ", allowed \"error\", \"warning\", \"notice\", \"info\" or \"debug\"");
            return true;
          },
          "level");
    } else if (key == "state") {
      read_state(TableReader(file, as_table(file, node, key), "state."), config);
    } else if (key == "ros") {
      read_ros(TableReader(file, as_table(file, node, key), "ros."), config.dds.ros);
    } else if (key == "record") {
      read_record(TableReader(file, as_table(file, node, key), "record."), config);
    } else {
      fail(file, node, key,
           "is not a known section (known: [sensor], [estimator], [dds], [ros], [state], [record], [log])");
    }
  }
  const auto& sec = config.dds.security;
  if (sec.enabled) {
    for (const auto& [key, value] : {std::pair<const char*, const std::string&>{"identity_ca", sec.identity_ca},
                                     {"certificate", sec.certificate},
                                     {"private_key", sec.private_key},
                                     {"permissions_ca", sec.permissions_ca},
                                     {"governance", sec.governance},
                                     {"permissions", sec.permissions}}) {
      if (value.empty()) throw ConfigError(file + ": [dds.security]: '" + key + "' is required when enabled = true");
      if (!std::ifstream(value))
        throw ConfigError(file + ": [dds.security]: " + key + " file " + value + " cannot be read");
    }
  }
  if (const auto problem = core::validate(config.estimator)) {
    throw ConfigError(file + ": [estimator]: " + *problem);
  }
  return config;
}

}  // namespace

Config parse_config(std::string_view text, const std::string& name) {
  try {
    const toml::table root = toml::parse(text, name);
    return interpret(root, name);
  } catch (const toml::parse_error& error) {
    const auto& begin = error.source().begin;
    throw ConfigError(name + ":" + std::to_string(begin.line) + ":" + std::to_string(begin.column) + ": " +
                      std::string(error.description()));
  }
}

bool apply_method_option(const std::optional<std::string>& method, core::EstimatorSettings& settings) {
  if (!method) return true;
  const auto parsed = core::parse_method(*method);
  if (!parsed) {
    std::fprintf(stderr, "headingd: --method: '%s' is not a method (use auto, a, b or c)\n", method->c_str());
    return false;
  }
  settings.method = *parsed;
  return true;
}

Config load_config(const std::string& path) {
  // A directory would read as an empty file (all defaults), a FIFO would block start-up and a
  // device would never end: only a regular file of sane size is a configuration.
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0) throw ConfigError("cannot open config " + path + ": " + std::strerror(errno));
  if (!S_ISREG(info.st_mode)) {
    const char* what = S_ISDIR(info.st_mode)                            ? "a directory"
                       : S_ISFIFO(info.st_mode)                         ? "a FIFO"
                       : S_ISCHR(info.st_mode) || S_ISBLK(info.st_mode) ? "a device"
                                                                        : "not a regular file";
    throw ConfigError("config " + path + " is " + what + ", not a configuration file");
  }
  constexpr off_t kMaxConfigBytes = 1 << 20;
  if (info.st_size > kMaxConfigBytes) throw ConfigError("config " + path + " is larger than 1 MiB");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ConfigError("cannot open config " + path + ": " + std::strerror(errno));
  std::ostringstream text;
  text << in.rdbuf();
  return parse_config(text.str(), path);
}

}  // namespace headingd::app
