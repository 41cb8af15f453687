#pragma once
#include <string>

#include "headingd.h"
#include "ros2_msgs.h"

namespace headingd::app {

// One line per message for `headingd echo`: every field, enums by name, text or JSON.
std::string line_for(const headingd::msg::Orientation& m, bool json);
std::string line_for(const headingd::msg::GyroBias& m, bool json);
std::string line_for(const headingd::msg::Status& m, bool json);
std::string line_for(const sensor_msgs::msg::dds_::Imu_& m, bool json);
std::string line_for(const headingd::msg::HeadingCommand& m, bool json);

}  // namespace headingd::app
