#pragma once
#include <optional>
#include <string>
#include <vector>

#include "dds/command_validator.hpp"
#include "dds/ros_settings.hpp"

namespace headingd::app {

// DDS Security (Fast DDS's builtin plugins): authentication with a PKI, access control by
// signed governance and permissions, encryption. File paths; all required when enabled.
struct DdsSecurity {
  bool enabled = false;
  std::string identity_ca;     // CA certificate that signed every identity (PEM)
  std::string certificate;     // this participant's identity certificate (PEM)
  std::string private_key;     // its private key (PEM)
  std::string permissions_ca;  // CA that signed governance and permissions
  std::string governance;      // signed governance document (S/MIME)
  std::string permissions;     // signed permissions document (S/MIME)
};

// How messages travel between processes on this host.
//  - Udp: UDP only (loopback and the host's interfaces), no shared memory and no data sharing.
//    Works between Unix users and between containers that share no IPC: the default.
//  - SharedMemory: Fast DDS's builtin shared-memory transport and data sharing besides UDP.
//    Fast DDS 2.9 creates its /dev/shm segments readable by their owner's user only (it has no
//    setting for their permissions), so only processes of the same user (and IPC namespace)
//    can take them; others fall back to nothing at all. Opt in only for that case.
enum class DdsTransport { Udp, SharedMemory };

// What to do on finding another publisher of our topics on the domain (a second headingd with
// the same prefix, a replay): subscribers would get both streams interleaved.
enum class DuplicatePolicy { Warn, Refuse };

struct DdsSettings {
  int domain_id = 0;                // [0, 232]
  std::string prefix = "headingd";  // topics PREFIX/orientation, /bias, /status, /command
  bool ros2_naming = false;         // our topics as ROS 2 names them on the wire: rt/PREFIX/...
  bool publish_imu = true;          // sensor_msgs/msg/Imu on the ROS topic IMU_TOPIC (REP-145's name)
  std::string imu_topic = "imu/data";
  std::string frame_id = "imu_link";
  double orientation_rate_hz = 50.0;        // Orientation and Imu messages per second (0, 1000]
  bool orientation_reliable = false;        // false: best-effort (latest wins); true: reliable
  double orientation_deadline_periods = 0;  // deadline QoS offered, in periods; 0: none (no timer per write)
  std::optional<std::string> profiles_xml;  // Fast DDS XML profiles (override our QoS)
  DdsTransport transport = DdsTransport::Udp;
  // Refuse: the instance that started later exits 75 (EX_TEMPFAIL); both log the conflict.
  DuplicatePolicy on_duplicate = DuplicatePolicy::Warn;  // unless a "headingd" participant profile says otherwise
  // Fast DDS Discovery Servers as IPV4:PORT, the position in the list being the server id
  // (`fastdds discovery -i ID`), as in ROS_DISCOVERY_SERVER; "" skips an id. Empty: multicast.
  std::vector<std::string> discovery_servers;
  CommandLimits command_limits;
  DdsSecurity security;
  RosSettings ros;  // the ROS 2 face: node, Imu semantics, diagnostics, temperature, stop hints
};

// The topic name for one of our topics, with the naming in force.
inline std::string topic_name(const DdsSettings& s, const std::string& leaf) {
  return (s.ros2_naming ? "rt/" : "") + s.prefix + "/" + leaf;
}

}  // namespace headingd::app
