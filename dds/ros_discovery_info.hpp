#pragma once
// ros_discovery_info (rmw_dds_common/msg/ParticipantEntitiesInfo): which ROS node owns which
// readers and writers of a participant. ROS 2's graph (`ros2 node list`, `ros2 topic info -v`)
// is built from it, so without it headingd's topics show up with no node. Published once,
// reliable and transient-local (depth 1) as rmw does, so a tool that starts later gets it.
#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <vector>

#include "dds/ros_settings.hpp"

namespace headingd::app {

// The topic name rmw uses: not under "rt/", it is not a ROS topic.
inline constexpr const char* kRosDiscoveryTopic = "ros_discovery_info";

// Creates the writer and publishes our node with the GUIDs of `readers` and `writers` as its
// GIDs. Returns the writer (deleted with the participant). Throws std::runtime_error.
eprosima::fastdds::dds::DataWriter* publish_ros_discovery_info(
    eprosima::fastdds::dds::DomainParticipant& participant, eprosima::fastdds::dds::Publisher& publisher,
    const RosSettings& ros, const std::vector<const eprosima::fastdds::dds::DataReader*>& readers,
    const std::vector<const eprosima::fastdds::dds::DataWriter*>& writers);

}  // namespace headingd::app
