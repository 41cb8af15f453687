// headingd's ROS 2 face without DDS: the Imu's fields per REP-145, the stop-hint tracker, the
// diagnostics levels, the [ros] settings, the heading across a restart, and the gyro winning
// over a wrong "stopped" hint.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "core/estimator.hpp"
#include "core/units.hpp"
#include "dds/imu_message.hpp"
#include "dds/ros_diagnostics.hpp"
#include "dds/stop_hint.hpp"
#include "io/state_file.hpp"
#include "service/config_file.hpp"

using namespace headingd;
using app::ImuOrientation;
using app::RateWindow;
using app::RosSettings;
using core::Vec3;

namespace {

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();

core::Estimate running_estimate() {
  core::Estimate e;
  e.t_s = 100.0;
  e.heading_deg = 120.0;
  e.heading_sigma_deg = 0.5;
  e.bias_dps = Vec3(0.1, 0.2, 0.3);
  e.bias_sigma_dps = Vec3(0.01, 0.01, 0.002);
  e.in_startup = false;
  return e;
}

core::Diagnostics running_diagnostics() {
  core::Diagnostics d;
  d.in_startup = false;
  d.sigma_still_dps = Vec3(1.2, 1.1, 0.13);
  d.heading_fixes = 1;
  d.heading_fix_offset_deg = 30.0;
  d.last_still_t_s = 90.0;
  return d;
}

}  // namespace

TEST(ImuFields, StartUpRateIsNotProvidedAndAccelerationNever) {
  core::Estimate e = running_estimate();
  e.in_startup = true;
  RateWindow window;
  window.add(Vec3(1, 2, 3));
  const auto f = app::imu_fields(e, running_diagnostics(), window, RosSettings{});
  EXPECT_EQ(f.angular_velocity_covariance[0], -1.0);
  EXPECT_EQ(f.linear_acceleration_covariance[0], -1.0);
  const auto g = app::imu_fields(running_estimate(), running_diagnostics(), window, RosSettings{});
  EXPECT_GT(g.angular_velocity_covariance[0], 0.0);
  EXPECT_EQ(g.linear_acceleration_covariance[0], -1.0);
}

TEST(ImuFields, YawOnlyIsTheContinuousYawWithItsSigma) {
  RateWindow window;
  window.add(Vec3::Zero());
  const auto f = app::imu_fields(running_estimate(), running_diagnostics(), window, RosSettings{});
  const double yaw = 2.0 * std::atan2(f.orientation_xyzw[2], f.orientation_xyzw[3]);
  EXPECT_NEAR(yaw, core::deg_to_rad(120.0 - 30.0), 1e-12);
  EXPECT_EQ(f.orientation_xyzw[0], 0.0);
  EXPECT_EQ(f.orientation_xyzw[1], 0.0);
  EXPECT_NEAR(f.orientation_covariance[8], std::pow(core::deg_to_rad(0.5), 2), 1e-15);
  EXPECT_NEAR(f.orientation_covariance[0], M_PI * M_PI, 1e-12);
  EXPECT_NEAR(f.orientation_covariance[4], M_PI * M_PI, 1e-12);
}

TEST(ImuFields, NoZeroVarianceThatReadsAsExact) {
  core::Estimate e = running_estimate();
  e.heading_sigma_deg = 0.0;  // held during start-up
  RateWindow window;
  window.add(Vec3::Zero());
  const auto f = app::imu_fields(e, running_diagnostics(), window, RosSettings{});
  EXPECT_GT(f.orientation_covariance[8], 0.0);
}

TEST(ImuFields, RateIsTheMeanAndItsVarianceTheMeansNoisePlusTheBias) {
  RateWindow window;
  std::mt19937_64 rng(5);
  std::normal_distribution<double> n(0.0, 1.0);
  Vec3 sum = Vec3::Zero();
  for (int i = 0; i < 8; ++i) {
    const Vec3 r(n(rng), n(rng), n(rng));
    sum += r;
    window.add(r);
  }
  const auto f = app::imu_fields(running_estimate(), running_diagnostics(), window, RosSettings{});
  for (int a = 0; a < 3; ++a)
    EXPECT_NEAR(f.angular_velocity_rad_s[static_cast<std::size_t>(a)], sum[a] / 8.0 * core::kRadPerDeg, 1e-15);
  const double sample = 0.13 * core::kRadPerDeg, bias = 0.002 * core::kRadPerDeg;
  EXPECT_NEAR(f.angular_velocity_covariance[8], sample * sample / 8.0 + bias * bias, 1e-18);
  EXPECT_EQ(f.angular_velocity_covariance[1], 0.0);
}

TEST(ImuFields, PaperMethodsSayCovarianceUnknownAndOverridesWin) {
  core::Estimate e = running_estimate();
  e.heading_sigma_deg = kNan;
  e.bias_sigma_dps = Vec3::Constant(kNan);
  RateWindow window;
  window.add(Vec3::Zero());
  auto f = app::imu_fields(e, running_diagnostics(), window, RosSettings{});
  for (double v : f.orientation_covariance) EXPECT_EQ(v, 0.0);
  for (double v : f.angular_velocity_covariance) EXPECT_EQ(v, 0.0);
  RosSettings ros;
  ros.orientation_stddev_rad = 0.1;
  ros.angular_velocity_stddev_rad_s = 0.01;
  ros.imu_orientation = ImuOrientation::Attitude;
  f = app::imu_fields(e, running_diagnostics(), window, ros);
  EXPECT_NEAR(f.orientation_covariance[8], 0.01, 1e-15);
  EXPECT_NEAR(f.angular_velocity_covariance[4], 1e-4, 1e-18);
  EXPECT_EQ(f.orientation_xyzw[3], 1.0);  // the attitude (identity here)
}

TEST(StopHint, StoppedAfterHoldMovingAtOnceStaleIsNothing) {
  app::StopHintSettings s;
  s.hold_s = 0.5;
  s.stale_s = 0.5;
  app::StopHintTracker tracker(s, app::CommandLimits{});
  std::string why;
  app::MotionReport still;
  still.stamp_s = 1000.0;
  ASSERT_TRUE(tracker.offer(still, 1000.0, why));
  EXPECT_EQ(tracker.hint(1000.2), core::MotionHint::None) << "not yet held";
  still.stamp_s = 1000.4;
  ASSERT_TRUE(tracker.offer(still, 1000.4, why));
  EXPECT_EQ(tracker.hint(1000.6), core::MotionHint::Stopped);
  EXPECT_EQ(tracker.hint(1001.0), core::MotionHint::None) << "stale";
  app::MotionReport moving;
  moving.stamp_s = 1001.0;
  moving.linear_m_s = Vec3(0.5, 0, 0);
  ASSERT_TRUE(tracker.offer(moving, 1001.0, why));
  EXPECT_EQ(tracker.hint(1001.0), core::MotionHint::Moving);
  app::MotionReport turning;  // a vehicle turning on the spot is not stopped
  turning.angular_rad_s = Vec3(0, 0, 0.3);
  ASSERT_TRUE(tracker.offer(turning, 1001.1, why));
  EXPECT_EQ(tracker.hint(1001.1), core::MotionHint::Moving);
  EXPECT_EQ(tracker.accepted(), 4u);
}

TEST(StopHint, NanStaleAndFutureAreRefusedAndChangeNothing) {
  app::StopHintTracker tracker(app::StopHintSettings{}, app::CommandLimits{});
  std::string why;
  app::MotionReport bad;
  bad.stamp_s = 1000.0;
  bad.linear_m_s = Vec3(kNan, 0, 0);
  EXPECT_FALSE(tracker.offer(bad, 1000.0, why));
  EXPECT_NE(why.find("finite"), std::string::npos);
  bad.linear_m_s = Vec3::Zero();
  bad.stamp_s = 900.0;
  EXPECT_FALSE(tracker.offer(bad, 1000.0, why));
  EXPECT_NE(why.find("stale"), std::string::npos);
  bad.stamp_s = 1100.0;
  EXPECT_FALSE(tracker.offer(bad, 1000.0, why));
  EXPECT_NE(why.find("future"), std::string::npos);
  bad.stamp_s = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(tracker.offer(bad, 1000.0, why));
  EXPECT_EQ(tracker.refused(), 4u);
  EXPECT_EQ(tracker.accepted(), 0u);
  EXPECT_EQ(tracker.hint(1000.0), core::MotionHint::None);
}

TEST(RosDiagnostics, LevelsFollowFaultsAndSigma) {
  RosSettings ros;
  ros.hardware_id = "L3GD20H 0x6b on /dev/i2c-1";
  app::DiagnosticsBuilder builder(ros);
  app::StatusReport report;
  report.state = app::SensorState::Ok;
  report.sample_rate_hz = 378.8;
  report.nominal_rate_hz = 400.0;
  core::Estimate e = running_estimate();
  auto entries = builder.build(e, running_diagnostics(), report, {});
  ASSERT_EQ(entries.size(), 2u);
  EXPECT_EQ(entries[0].name, "headingd: sensor");
  EXPECT_EQ(entries[0].hardware_id, ros.hardware_id);
  EXPECT_EQ(entries[0].level, app::DiagnosticLevel::Ok);
  EXPECT_EQ(entries[1].level, app::DiagnosticLevel::Ok);
  report.bus_errors = 3;
  e.t_s = 101.0;
  entries = builder.build(e, running_diagnostics(), report, {});
  EXPECT_EQ(entries[0].level, app::DiagnosticLevel::Warn);
  e.t_s = 112.0;  // 11 s later, nothing new: OK again
  entries = builder.build(e, running_diagnostics(), report, {});
  EXPECT_EQ(entries[0].level, app::DiagnosticLevel::Ok);
  report.stuck_samples = 400;
  entries = builder.build(e, running_diagnostics(), report, {});
  EXPECT_EQ(entries[0].level, app::DiagnosticLevel::Error);
  e.heading_sigma_deg = 40.0;
  entries = builder.build(e, running_diagnostics(), report, {});
  EXPECT_EQ(entries[1].level, app::DiagnosticLevel::Error);
  core::Diagnostics starting = running_diagnostics();
  starting.in_startup = true;  // the held heading's sigma: a turn the start-up could hide, for seconds
  entries = builder.build(e, starting, report, {});
  EXPECT_EQ(entries[1].level, app::DiagnosticLevel::Warn) << "no heading to set while the start-up measures";
  e.heading_sigma_deg = 6.0;
  entries = builder.build(e, running_diagnostics(), report, {});
  EXPECT_EQ(entries[1].level, app::DiagnosticLevel::Warn);
  report.sample_rate_hz = 300.0;
  report.stuck_samples = 0;
  entries = builder.build(e, running_diagnostics(), report, {});
  EXPECT_EQ(entries[0].level, app::DiagnosticLevel::Warn) << "rate 25 % off nominal";
  const auto has_key = [](const app::DiagnosticEntry& entry, const std::string& key) {
    for (const auto& [k, v] : entry.values)
      if (k == key) return true;
    return false;
  };
  EXPECT_FALSE(has_key(entries[1], "scale_z")) << "no scale learned, none shown";
  core::Diagnostics learned = running_diagnostics();
  learned.scale_z = 0.012;
  learned.scale_z_sigma = 0.002;
  entries = builder.build(e, learned, report, {});
  EXPECT_TRUE(has_key(entries[1], "scale_z") && has_key(entries[1], "scale_z_sigma"));
  for (const char* key :
       {"bias_restarts", "bias_restarts_taken_back", "bias_restarts_refused", "bias_restarts_of_saved_state",
        "returns_mended", "gaps_bridged", "temperature_models_refuted", "rejected_rate_changing"})
    EXPECT_TRUE(has_key(entries[1], key)) << key;
}

TEST(RosDiagnostics, ABiasRestartAndAHeadingCorrectionWarnForTenSeconds) {
  app::DiagnosticsBuilder builder{RosSettings{}};
  app::StatusReport report;
  report.state = app::SensorState::Ok;
  core::Estimate e = running_estimate();
  core::Diagnostics d = running_diagnostics();
  EXPECT_EQ(builder.build(e, d, report, {})[1].level, app::DiagnosticLevel::Ok);
  d.bias_recoveries = 1;
  e.t_s = 101.0;
  auto entries = builder.build(e, d, report, {});
  EXPECT_EQ(entries[1].level, app::DiagnosticLevel::Warn);
  EXPECT_NE(entries[1].message.find("bias restarted"), std::string::npos) << entries[1].message;
  e.t_s = 112.0;
  EXPECT_EQ(builder.build(e, d, report, {})[1].level, app::DiagnosticLevel::Ok);
  d.returns_mended = 1;
  d.last_return_correction_deg = -42.6;
  e.t_s = 200.0;
  entries = builder.build(e, d, report, {});
  EXPECT_EQ(entries[1].level, app::DiagnosticLevel::Warn);
  EXPECT_NE(entries[1].message.find("heading corrected by -42.6 deg"), std::string::npos) << entries[1].message;
  e.t_s = 211.0;
  EXPECT_EQ(builder.build(e, d, report, {})[1].level, app::DiagnosticLevel::Ok);
}

TEST(RosDiagnostics, AFileOutputNotWritingWarnsUntilItWritesAgain) {
  app::DiagnosticsBuilder builder{RosSettings{}};
  app::StatusReport report;
  report.state = app::SensorState::Ok;
  core::Estimate e = running_estimate();
  EXPECT_EQ(builder.build(e, running_diagnostics(), report, {})[0].level, app::DiagnosticLevel::Ok);
  report.outputs_dropped = 1;
  report.outputs_failing = 1;
  report.output_dropped = "recording: cannot write /var/log/rec.csv: No space left on device";
  for (const double t_s : {101.0, 5000.0}) {  // not only the ten seconds after it
    e.t_s = t_s;
    const auto entries = builder.build(e, running_diagnostics(), report, {});
    EXPECT_EQ(entries[0].level, app::DiagnosticLevel::Warn);
    EXPECT_NE(entries[0].message.find("No space left on device"), std::string::npos) << entries[0].message;
    bool counted = false;
    for (const auto& [key, value] : entries[0].values)
      counted = counted || (key == "file_outputs_dropped" && value == "1");
    EXPECT_TRUE(counted);
  }
  // A rolling recording that started a file which writes again: OK, the count kept.
  report.outputs_failing = 0;
  e.t_s = 6000.0;
  const auto entries = builder.build(e, running_diagnostics(), report, {});
  EXPECT_EQ(entries[0].level, app::DiagnosticLevel::Ok) << entries[0].message;
  bool counted = false;
  for (const auto& [key, value] : entries[0].values)
    counted = counted || (key == "file_outputs_dropped" && value == "1");
  EXPECT_TRUE(counted);
}

TEST(RosConfig, ReadsTheRosTablesAndRefusesBadNames) {
  const auto config = app::parse_config(R"(
[dds]
imu_topic = "/imu/data"
[ros]
node_name = "gyro"
namespace = "/robot_1/front"
distro = "humble"
imu_orientation = "attitude"
angular_velocity_stddev_rad_s = 0.002
[ros.stop_hint]
topic = "wheel/odom"
type = "twist_stamped"
hold_s = 1.5
)",
                                        "t.toml");
  const RosSettings& ros = config.dds.ros;
  EXPECT_EQ(ros.node_name, "gyro");
  EXPECT_EQ(ros.distro, app::RosDistro::Humble);
  EXPECT_EQ(ros.imu_orientation, ImuOrientation::Attitude);
  EXPECT_EQ(ros.stop_hint.type, app::StopHintType::TwistStamped);
  EXPECT_DOUBLE_EQ(ros.stop_hint.hold_s, 1.5);
  EXPECT_EQ(app::ros_topic(ros, config.dds.imu_topic), "rt/imu/data");
  EXPECT_EQ(app::ros_topic(ros, ros.stop_hint.topic), "rt/robot_1/front/wheel/odom");
  for (const char* bad :
       {"[ros]\nnode_name = \"a/b\"", "[ros]\nnamespace = \"robot\"", "[ros]\nnamespace = \"/a//b\"",
        "[ros.stop_hint]\ntopic = \"1odom\"", "[ros.stop_hint]\ntopic = \"odom/\"", "[ros]\ndistro = \"foxy\"",
        "[ros.stop_hint]\ntype = \"pose\"", "[dds]\nimu_topic = \"imu data\""}) {
    try {
      app::parse_config(bad, "t.toml");
      ADD_FAILURE() << "accepted: " << bad;
    } catch (const app::ConfigError& error) {
      EXPECT_NE(std::string(error.what()).find("t.toml:"), std::string::npos) << error.what();
    }
  }
}

TEST(HeadingAcrossRestart, StateFileCarriesHeadingSigmaAndOffset) {
  core::Estimator first;
  core::Sample s;
  for (int i = 0; i < 4000; ++i) {
    s.t_s = i / 400.0;
    s.rate_dps = Vec3(0.1, 0.2, 0.3 + (i > 2000 ? 10.0 : 0.0));
    first.update(s);
  }
  first.set_heading(45.0, 0.0);
  for (int i = 4000; i < 4400; ++i) {
    s.t_s = i / 400.0;
    first.update(s);
  }
  app::SavedState saved;
  static_cast<core::LearnedState&>(saved) = first.learned();
  const app::SavedState back = app::parse_state(app::format_state(saved), "mem");
  EXPECT_DOUBLE_EQ(back.heading_deg, first.last().heading_deg);
  EXPECT_DOUBLE_EQ(back.heading_fix_offset_deg, first.diagnostics().heading_fix_offset_deg);
  core::Estimator second;
  second.restore(back);
  s.t_s = 0.0;
  s.rate_dps = Vec3(0.1, 0.2, 0.3);
  second.update(s);
  EXPECT_NEAR(second.last().heading_deg, first.last().heading_deg, 1e-3);
  EXPECT_NEAR(second.last().heading_sigma_deg, first.last().heading_sigma_deg, 1e-3);
  EXPECT_DOUBLE_EQ(second.diagnostics().heading_fix_offset_deg, first.diagnostics().heading_fix_offset_deg);
  EXPECT_EQ(second.diagnostics().heading_fixes, 0u) << "a restore is not a fix";
  core::Estimator fresh;
  fresh.restore(back, false);
  fresh.update(s);
  EXPECT_NEAR(fresh.last().heading_deg, 0.0, 1e-3);
}

TEST(HeadingAcrossRestart, CorruptHeadingIsRefused) {
  app::SavedState saved;
  saved.heading_deg = 1e300;
  saved.heading_variance_deg2 = 1.0;
  EXPECT_THROW(app::parse_state(app::format_state(saved), "mem"), app::StateError);
}

TEST(StoppedHint, TheGyroWinsOverAVehicleThatSaysStoppedWhileTurning) {
  core::Estimator estimator;
  core::Sample s;
  std::mt19937_64 rng(3);
  std::normal_distribution<double> n(0.0, 0.05);
  int i = 0;
  const auto run = [&](double seconds, double rate_dps) {
    int accepted = 0;
    for (const int end = i + static_cast<int>(seconds * 400); i < end; ++i) {
      s.t_s = i / 400.0;
      s.rate_dps = Vec3(0.1 + n(rng), 0.2 + n(rng), 0.3 + rate_dps + n(rng));
      accepted += estimator.update(s).closed.accepted ? 1 : 0;
    }
    return accepted;
  };
  run(20.0, 0.0);
  estimator.set_motion_hint(core::MotionHint::Stopped);
  run(0.5, 2.0);  // closes the still segment the turn cut short (that one was still)
  EXPECT_EQ(run(15.0, 2.0), 0) << "a 2 dps turn is no stop, whatever the vehicle says";
  EXPECT_GE(estimator.diagnostics().hint_conflicts, 4u);
  EXPECT_NEAR(estimator.last().bias_dps.z(), 0.3, 0.02) << "the bias did not take the turn";
}

// Issue 15 item 3: a NaN that got past every input check (injected straight into the estimator)
// must not come out as a NaN heading with sigma 0: the estimate freezes with an infinite sigma,
// the fault is flagged, what is saved is the last healthy state, and the Imu says "not provided".
TEST(OutputInvariant, NanPastEveryGuardBecomesAFaultNeverNanWithSigmaZero) {
  for (const core::Method method : {core::Method::Auto, core::Method::C}) {
    core::EstimatorSettings settings;
    settings.method = method;
    core::Estimator estimator(settings);
    core::Sample s;
    for (int i = 0; i < 2400; ++i) {
      s.t_s = i / 400.0;
      s.rate_dps = Vec3(0.1, 0.2, 0.3 + (i > 1600 ? 5.0 : 0.0));
      estimator.update(s);
    }
    const double heading_before = estimator.last().heading_deg;
    s.t_s += 0.0025;
    s.rate_dps = Vec3(0.1, kNan, 0.3);  // past the door: only a test can do this
    for (int i = 0; i < 1200; ++i) {
      s.t_s += 0.0025;
      const core::Estimate& e = estimator.update(s);
      ASSERT_TRUE(std::isfinite(e.heading_deg)) << "method " << core::method_name(method);
      ASSERT_TRUE(e.fault);
      ASSERT_TRUE(std::isinf(e.heading_sigma_deg) && e.heading_sigma_deg > 0);
      ASSERT_TRUE(e.attitude.coeffs().allFinite() && e.bias_dps.allFinite() && e.rate_dps.allFinite());
    }
    EXPECT_NEAR(estimator.last().heading_deg, heading_before, 0.1);
    EXPECT_TRUE(estimator.fault());
    const core::LearnedState saved = estimator.learned();
    EXPECT_FALSE(core::implausible(saved).has_value()) << *core::implausible(saved);
    app::SavedState file;
    static_cast<core::LearnedState&>(file) = saved;
    EXPECT_NO_THROW(app::parse_state(app::format_state(file), "mem"));
    RateWindow window;
    window.add(estimator.last().rate_dps);
    const auto imu = app::imu_fields(estimator.last(), estimator.diagnostics(), window, RosSettings{});
    EXPECT_EQ(imu.orientation_covariance[0], -1.0);
    EXPECT_EQ(imu.angular_velocity_covariance[0], -1.0);
  }
}

TEST(OutputInvariant, AbsurdStateIsRefusedBeforeItTouchesTheEstimator) {
  app::SavedState state;
  state.bias_sigma_dps = Vec3::Constant(1e160);  // a valid checksum does not make it sane
  EXPECT_THROW(app::parse_state(app::format_state(state), "mem"), app::StateError);
  core::LearnedState learned;
  learned.bias_sigma_dps = Vec3::Constant(1e160);
  core::Estimator estimator;
  EXPECT_THROW(estimator.restore(learned), std::invalid_argument);
  learned.bias_sigma_dps = Vec3::Constant(0.01);
  learned.sigma_still_dps = Vec3(kNan, 1, 1);
  EXPECT_THROW(estimator.restore(learned), std::invalid_argument);
  core::Sample s;
  s.rate_dps = Vec3(0.1, 0.2, 0.3);
  EXPECT_TRUE(std::isfinite(estimator.update(s).heading_deg));
  EXPECT_FALSE(estimator.fault());
}

TEST(OutputInvariant, TheDoorRefusesWhatNoGyroReports) {
  core::Sample s;
  EXPECT_TRUE(core::plausible(s));
  s.rate_dps.z() = 1e308;
  EXPECT_FALSE(core::plausible(s));
  EXPECT_NE(core::why_implausible(s)->find("rate z"), std::string::npos);
  s.rate_dps.z() = 0.0;
  s.temp_c = 200.0;
  EXPECT_FALSE(core::plausible(s));
  s.temp_c = kNan;  // unknown is fine
  EXPECT_TRUE(core::plausible(s));
  s.t_s = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(core::plausible(s));
}
