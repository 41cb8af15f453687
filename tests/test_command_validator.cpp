#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "dds/command_validator.hpp"

using namespace headingd::app;

namespace {
constexpr double kNow = 1'700'000'000.5;
CommandIn at(double stamp_s, int kind, double heading_rad = 0.0, double variance = 0.0) {
  CommandIn c;
  c.stamp_sec = static_cast<std::int32_t>(std::floor(stamp_s));
  c.stamp_nanosec = static_cast<std::uint32_t>((stamp_s - std::floor(stamp_s)) * 1e9);
  c.kind = kind;
  c.heading_rad = heading_rad;
  c.heading_variance_rad2 = variance;
  return c;
}
}  // namespace

TEST(CommandValidator, AcceptsAFreshSetHeadingInDegrees) {
  std::string why;
  const auto v = validate_command(at(kNow - 0.2, 0, M_PI / 2, 0.01), kNow, {}, why);
  ASSERT_TRUE(v.has_value()) << why;
  EXPECT_EQ(v->kind, CommandKind::SetHeading);
  EXPECT_NEAR(v->heading_deg, 90.0, 1e-9);
  EXPECT_NEAR(v->variance_deg2, 0.01 * (180 / M_PI) * (180 / M_PI), 1e-9);
}

TEST(CommandValidator, HintsMapToMotionHints) {
  std::string why;
  EXPECT_EQ(validate_command(at(kNow, 1), kNow, {}, why)->hint, headingd::core::MotionHint::Stopped);
  EXPECT_EQ(validate_command(at(kNow, 2), kNow, {}, why)->hint, headingd::core::MotionHint::Moving);
  EXPECT_EQ(validate_command(at(kNow, 3), kNow, {}, why)->hint, headingd::core::MotionHint::None);
}

TEST(CommandValidator, RefusesMalformedOutOfRangeAndStale) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  struct Case {
    CommandIn command;
    const char* reason;
  } cases[] = {
      {at(kNow, 0, nan), "heading_rad"},    {at(kNow, 0, inf), "heading_rad"},     {at(kNow, 0, 1e9), "heading_rad"},
      {at(kNow, 0, 1.0, -1.0), "variance"}, {at(kNow, 0, 1.0, nan), "variance"},   {at(kNow - 60, 0, 1.0), "stale"},
      {at(kNow + 30, 0, 1.0), "future"},    {at(kNow, 7), "unknown command kind"},
  };
  for (const auto& c : cases) {
    std::string why;
    EXPECT_FALSE(validate_command(c.command, kNow, {}, why).has_value()) << c.reason;
    EXPECT_NE(why.find(c.reason), std::string::npos) << why;
  }
  CommandIn bad_ns = at(kNow, 1);
  bad_ns.stamp_nanosec = 1'500'000'000u;
  std::string why;
  EXPECT_FALSE(validate_command(bad_ns, kNow, {}, why).has_value());
  EXPECT_NE(why.find("nanosec"), std::string::npos);
}
