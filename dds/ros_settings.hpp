#pragma once
// What headingd says in ROS 2 terms: the node ROS tools list, the Imu's semantics (REP-145,
// REP-103), /diagnostics (REP-107), the chip temperature, and the topic a vehicle may use to
// tell us it stands still. Plain settings; dds_node maps them onto DDS.
#include <optional>
#include <string>

namespace headingd::app {

// What the Imu's orientation carries.
//  - YawOnly: a rotation about z by the continuous yaw (our heading minus the fixes' offset);
//    roll and pitch are not estimated and get the variance of an angle known only to lie in
//    +-pi. Suits ground vehicles and robot_localization in two_d_mode.
//  - Attitude: the gyro-integrated attitude from all three axes (roll and pitch drift).
enum class ImuOrientation { YawOnly, Attitude };

// The layout of rmw_dds_common's Gid on ros_discovery_info: 24 bytes up to Humble, 16 from
// Iron on (Jazzy, Kilted). ROS 2 distributions do not talk to each other anyway.
enum class RosDistro { Humble, Jazzy };

// Which message carries the vehicle's own motion.
enum class StopHintType { Odometry, Twist, TwistStamped };

struct StopHintSettings {
  std::string topic;  // ROS name; "" = no hint topic. Relative names go under the namespace.
  StopHintType type = StopHintType::Odometry;
  // Below both for hold_s: stopped. Above either: moving (at once).
  double linear_stopped_m_s = 0.01;
  double angular_stopped_rad_s = 0.01;
  double hold_s = 0.5;
  // No message for this long (or one stamped this far in the past): no hint at all.
  double stale_s = 0.5;
};

struct RosSettings {
  std::string node_name = "headingd";
  std::string node_namespace = "/";  // "/" or "/a/b": every relative topic goes under it
  RosDistro distro = RosDistro::Jazzy;
  bool discovery_info = true;  // publish ros_discovery_info so `ros2 node list` shows us
  ImuOrientation imu_orientation = ImuOrientation::YawOnly;
  // Replace our own figures in the Imu (as phidgets' and other drivers' ~*_stddev parameters).
  std::optional<double> orientation_stddev_rad;
  std::optional<double> angular_velocity_stddev_rad_s;
  bool diagnostics = true;                            // /diagnostics at 1 Hz
  std::string temperature_topic = "imu/temperature";  // sensor_msgs/Temperature at 1 Hz; "" = none
  // Estimator status on /diagnostics: WARN and ERROR above these heading sigmas, WARN when the
  // last accepted still segment is older than still_age_warn_s.
  double heading_sigma_warn_deg = 5.0;
  double heading_sigma_error_deg = 30.0;
  double still_age_warn_s = 3600.0;
  std::string hardware_id = "unknown";  // set from the source: "L3GD20H 0x6b on /dev/i2c-1"
  StopHintSettings stop_hint;
};

// The DDS topic for a ROS name: "rt" + the fully qualified name (ROS 2's mapping).
inline std::string ros_topic(const RosSettings& ros, const std::string& name) {
  if (!name.empty() && name.front() == '/') return "rt" + name;
  return "rt" + (ros.node_namespace == "/" ? std::string() : ros.node_namespace) + "/" + name;
}

}  // namespace headingd::app
