// `headingd echo` lines: every field present, enums by name, and JSON that stays JSON when a
// value is NaN (an unknown variance or temperature is normal, not an error).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "dds/message_format.hpp"
#include "dds/message_line.hpp"

using headingd::app::line_for;
using headingd::app::MessageLine;

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
}

TEST(MessageLine, TextAndJsonShapes) {
  const auto build = [](bool json) {
    return MessageLine("t", json).count("n", 3).numbers("v", {1.5, -2.0}).flag("ok", true).text("s", "a\"b").str();
  };
  EXPECT_EQ(build(false), "t n=3 v=(1.5 -2) ok=1 s=a\"b");
  EXPECT_EQ(build(true), "{\"topic\":\"t\",\"n\":3,\"v\":[1.5,-2],\"ok\":true,\"s\":\"a\\\"b\"}");
}

TEST(MessageLine, NonFiniteIsNullInJsonEverywhere) {
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(MessageLine("t", true).number("x", kNaN).numbers("v", {kNaN, inf, 1.0}).fixed("f", -inf, 3).str(),
            "{\"topic\":\"t\",\"x\":null,\"v\":[null,null,1],\"f\":null}");
  EXPECT_EQ(MessageLine("t", false).number("x", kNaN).numbers("v", {inf, 1.0}).str(), "t x=nan v=(inf 1)");
}

TEST(MessageLine, ControlCharactersEscapedInJson) {
  EXPECT_EQ(MessageLine("t", true).text("s", "a\nb\\").str(), "{\"topic\":\"t\",\"s\":\"a\\u000ab\\\\\"}");
}

TEST(MessageFormat, GyroBiasHasEveryFieldAndNamesTheMethod) {
  headingd::msg::GyroBias b;
  b.stamp().sec(100);
  b.stamp().nanosec(500000000);
  b.bias_x_rad_s(0.001);
  b.sigma_x_rad_s(kNaN);
  b.temperature_c(31.25);
  b.accepted_segments(7);
  b.rejected_segments(2);
  b.method(headingd::msg::Method::METHOD_C);
  const std::string json = line_for(b, true);
  EXPECT_NE(json.find("\"stamp\":100.500000000"), std::string::npos) << json;
  EXPECT_NE(json.find("\"bias_rad_s\":[0.001,0,0]"), std::string::npos) << json;
  EXPECT_NE(json.find("\"sigma_rad_s\":[null,0,0]"), std::string::npos) << json;
  EXPECT_NE(json.find("\"temperature_c\":31.25"), std::string::npos) << json;
  EXPECT_NE(json.find("\"last_still\":null"), std::string::npos) << json;  // none accepted yet: stamp 0
  EXPECT_NE(json.find("\"accepted\":7,\"rejected\":2,\"method\":\"c\"}"), std::string::npos) << json;
  EXPECT_NE(line_for(b, false).find("method=c"), std::string::npos);
}

TEST(MessageFormat, StatusNamesTheStateAndKeepsCounterOrder) {
  headingd::msg::Status s;
  s.state(headingd::msg::SensorState::SENSOR_DEGRADED);
  s.commands_accepted(1);
  s.commands_rejected(2);
  s.version("0.1.0");
  const std::string json = line_for(s, true);
  EXPECT_NE(json.find("\"state\":\"degraded\""), std::string::npos) << json;
  EXPECT_NE(json.find("\"commands_accepted\":1,\"commands_rejected\":2"), std::string::npos) << json;
  EXPECT_NE(json.find("\"version\":\"0.1.0\"}"), std::string::npos) << json;
}

TEST(MessageFormat, OrientationWithUnknownVarianceIsStillJson) {
  headingd::msg::Orientation o;
  o.seq(42);
  o.heading_rad(1.5);
  o.heading_variance_rad2(kNaN);
  o.qw(1.0);
  o.still(true);
  const std::string json = line_for(o, true);
  EXPECT_NE(json.find("\"seq\":42,\"heading_rad\":1.500000000,\"heading_variance_rad2\":null"), std::string::npos)
      << json;
  EXPECT_NE(json.find("\"still\":true,\"heading_fixes\":0,\"yaw_offset_rad\":0.000000000}"), std::string::npos) << json;
  EXPECT_EQ(json.find("nan"), std::string::npos) << json;
}

TEST(MessageFormat, ImuShowsCovariancesAndFrame) {
  sensor_msgs::msg::dds_::Imu_ m;
  m.header().frame_id("imu_link");
  m.orientation_covariance()[8] = 0.0025;
  m.linear_acceleration_covariance()[0] = -1.0;
  const std::string text = line_for(m, false);
  EXPECT_NE(text.find("frame_id=imu_link"), std::string::npos) << text;
  EXPECT_NE(text.find("orientation_covariance_diag=(0 0 0.0025)"), std::string::npos) << text;
  EXPECT_NE(text.find("linear_acceleration_covariance0=-1"), std::string::npos) << text;
}

TEST(MessageFormat, CommandKindByName) {
  headingd::msg::HeadingCommand c;
  c.kind(headingd::msg::CommandKind::COMMAND_PLATFORM_STOPPED);
  EXPECT_NE(line_for(c, false).find("kind=platform_stopped"), std::string::npos);
}
