#include "dds/message_format.hpp"

#include <limits>

#include "dds/message_line.hpp"
#include "dds/status_report.hpp"
#include "dds/wire_method.hpp"

namespace headingd::app {

namespace {

using headingd::msg::CommandKind;
using headingd::msg::SensorState;

template <typename S>
double seconds(const S& stamp) {
  return stamp.sec() + stamp.nanosec() * 1e-9;
}

// Text lines are for reading: microseconds are enough there; JSON keeps the stamp whole.
MessageLine started(const char* topic, double stamp_s, bool json) {
  MessageLine line(topic, json);
  line.fixed("stamp", stamp_s, json ? 9 : 6);
  return line;
}

// The wire's SensorState has our StatusReport's order (dds/status_report.hpp), so one name table serves both.
static_assert(static_cast<int>(SensorState::SENSOR_STARTING) == static_cast<int>(app::SensorState::Starting) &&
              static_cast<int>(SensorState::SENSOR_OK) == static_cast<int>(app::SensorState::Ok) &&
              static_cast<int>(SensorState::SENSOR_DEGRADED) == static_cast<int>(app::SensorState::Degraded) &&
              static_cast<int>(SensorState::SENSOR_FAILED) == static_cast<int>(app::SensorState::Failed) &&
              static_cast<int>(SensorState::SENSOR_REPLAY) == static_cast<int>(app::SensorState::Replay));

const char* name_of(SensorState state) {
  const int value = static_cast<int>(state);
  return value >= 0 && value <= static_cast<int>(app::SensorState::Replay)
             ? sensor_state_name(static_cast<app::SensorState>(value))
             : "unknown";  // a newer peer's state we do not know
}

const char* name_of(CommandKind kind) {
  switch (kind) {
    case CommandKind::COMMAND_SET_HEADING:
      return "set_heading";
    case CommandKind::COMMAND_PLATFORM_STOPPED:
      return "platform_stopped";
    case CommandKind::COMMAND_PLATFORM_MOVING:
      return "platform_moving";
    case CommandKind::COMMAND_CLEAR_HINT:
      return "clear_hint";
  }
  return "unknown";
}

}  // namespace

std::string line_for(const headingd::msg::Orientation& m, bool json) {
  return started("orientation", seconds(m.stamp()), json)
      .count("seq", m.seq())
      .fixed("heading_rad", m.heading_rad(), 9)
      .number("heading_variance_rad2", m.heading_variance_rad2(), 6)
      .numbers("q", {m.qw(), m.qx(), m.qy(), m.qz()})
      .numbers("rate_rad_s", {m.rate_x_rad_s(), m.rate_y_rad_s(), m.rate_z_rad_s()}, 6)
      .flag("still", m.still())
      .count("heading_fixes", m.heading_fixes())
      .fixed("yaw_offset_rad", m.yaw_offset_rad(), 9)
      .str();
}

std::string line_for(const headingd::msg::GyroBias& m, bool json) {
  const double last_still = seconds(m.last_still());
  return started("bias", seconds(m.stamp()), json)
      .numbers("bias_rad_s", {m.bias_x_rad_s(), m.bias_y_rad_s(), m.bias_z_rad_s()})
      .numbers("sigma_rad_s", {m.sigma_x_rad_s(), m.sigma_y_rad_s(), m.sigma_z_rad_s()}, 6)
      .number("temperature_c", m.temperature_c(), 4)
      // A zero stamp means no still segment has been accepted yet.
      .fixed("last_still", last_still > 0.0 ? last_still : std::numeric_limits<double>::quiet_NaN(), json ? 9 : 6)
      .count("accepted", m.accepted_segments())
      .count("rejected", m.rejected_segments())
      .text("method", core::method_name(from_wire(m.method())))
      .str();
}

std::string line_for(const headingd::msg::Status& m, bool json) {
  return started("status", seconds(m.stamp()), json)
      .text("state", name_of(m.state()))
      .fixed("rate_hz", m.sample_rate_hz(), 3)
      .count("samples", m.samples_received())
      .count("dropped", m.samples_dropped())
      .count("bus_errors", m.bus_errors())
      .count("overruns", m.fifo_overruns())
      .count("commands_accepted", m.commands_accepted())
      .count("commands_rejected", m.commands_rejected())
      .fixed("uptime_s", m.uptime_s(), 3)
      .count("other_publishers", m.other_publishers())
      .count("motion_accepted", m.motion_messages_accepted())
      .count("motion_refused", m.motion_messages_refused())
      .text("version", m.version().c_str())
      .str();
}

std::string line_for(const sensor_msgs::msg::dds_::Imu_& m, bool json) {
  const auto& o = m.orientation_covariance();
  const auto& w = m.angular_velocity_covariance();
  const auto& stamp = m.header().stamp();
  return started("imu", stamp.sec() + stamp.nanosec() * 1e-9, json)
      .text("frame_id", m.header().frame_id())
      .numbers("q", {m.orientation().w(), m.orientation().x(), m.orientation().y(), m.orientation().z()})
      .numbers("orientation_covariance_diag", {o[0], o[4], o[8]}, 6)
      .numbers("angular_velocity", {m.angular_velocity().x(), m.angular_velocity().y(), m.angular_velocity().z()}, 6)
      .numbers("angular_velocity_covariance_diag", {w[0], w[4], w[8]}, 6)
      .number("linear_acceleration_covariance0", m.linear_acceleration_covariance()[0], 6)
      .str();
}

std::string line_for(const headingd::msg::HeadingCommand& m, bool json) {
  return started("command", seconds(m.stamp()), json)
      .text("kind", name_of(m.kind()))
      .number("heading_rad", m.heading_rad())
      .number("heading_variance_rad2", m.heading_variance_rad2(), 6)
      .str();
}

}  // namespace headingd::app
