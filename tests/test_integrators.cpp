#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "core/attitude_integrator.hpp"
#include "core/estimator.hpp"
#include "core/heading_integrator.hpp"
#include "core/units.hpp"

using namespace headingd::core;

namespace {

double angle_between(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) { return a.angularDistance(b); }

void rotate(AttitudeIntegrator& integrator, const Vec3& rate_dps, double seconds, int steps) {
  for (int i = 0; i < steps; ++i) integrator.add(rate_dps, seconds / steps);
}

}  // namespace

TEST(HeadingIntegrator, ConstantRateIsExact) {
  HeadingIntegrator heading;
  for (int i = 0; i < 4000; ++i) heading.add(10.5, 0.5, 0.0025);  // 10 dps net for 10 s
  EXPECT_NEAR(heading.heading_deg(), 100.0, 1e-9);
}

TEST(AttitudeIntegrator, KnownRotationSequence) {
  AttitudeIntegrator integrator;
  rotate(integrator, Vec3(0, 0, 90), 1.0, 400);   // yaw +90 deg
  rotate(integrator, Vec3(45, 0, 0), 2.0, 800);   // then roll +90 deg about the new x
  rotate(integrator, Vec3(0, -30, 0), 1.0, 333);  // then pitch -30 deg
  const Eigen::Quaterniond expected = Eigen::AngleAxisd(deg_to_rad(90), Vec3::UnitZ()) *
                                      Eigen::AngleAxisd(deg_to_rad(90), Vec3::UnitX()) *
                                      Eigen::AngleAxisd(deg_to_rad(-30), Vec3::UnitY());
  EXPECT_LT(angle_between(integrator.attitude(), expected), 1e-6);
}

TEST(AttitudeIntegrator, ConstantThreeAxisRateMatchesAxisAngle) {
  AttitudeIntegrator integrator;
  const Vec3 rate(3.0, -4.0, 12.0);  // |rate| = 13 dps
  rotate(integrator, rate, 10.0, 4000);
  const Eigen::Quaterniond expected(Eigen::AngleAxisd(deg_to_rad(130.0), rate.normalized()));
  EXPECT_LT(angle_between(integrator.attitude(), expected), 1e-6);
}

TEST(AttitudeIntegrator, EachAxisTurnAboutTheVerticalAddsUpToTheYaw) {
  AttitudeIntegrator integrator;
  rotate(integrator, Vec3(0, 0, 20), 1.0, 400);  // level: yaw +20 deg, all of it z's
  rotate(integrator, Vec3(0, 45, 0), 2.0, 800);  // pitch +90: x now points down
  rotate(integrator, Vec3(30, 0, 0), 1.0, 400);  // +30 about x: yaw -30 deg
  const Vec3 turned = integrator.vertical_turn_deg();
  EXPECT_NEAR(turned.x(), -30.0, 1e-6);
  EXPECT_NEAR(turned.y(), 0.0, 1e-6);
  EXPECT_NEAR(turned.z(), 20.0, 1e-6);
  // The twist about the vertical (as BROAD's heading error is taken) is their sum: q is
  // Rz(-10) Ry(90).
  const Eigen::Quaterniond& q = integrator.attitude();
  EXPECT_NEAR(rad_to_deg(2.0 * std::atan2(q.z(), q.w())), turned.sum(), 1e-6);
  rotate(integrator, Vec3(0, 0, 50), 1.0, 400);  // about z, horizontal now: no turn about the vertical
  EXPECT_NEAR(integrator.vertical_turn_deg().z(), 20.0, 1e-6);
}

TEST(AttitudeIntegrator, ForwardAndBackReturnsToStart) {
  AttitudeIntegrator integrator;
  rotate(integrator, Vec3(10, 20, 30), 1.0, 100);
  rotate(integrator, Vec3(-10, -20, -30), 1.0, 100);
  EXPECT_LT(angle_between(integrator.attitude(), Eigen::Quaterniond::Identity()), 1e-9);
}

TEST(Estimator, HoldsHeadingDuringStartupThenIntegratesBiasCorrectedRate) {
  EstimatorSettings settings;
  settings.method = Method::C;
  Estimator estimator(settings);
  Sample s;
  s.rate_dps = Vec3(0.1, 0.2, -0.5);
  int i = 0;
  for (; i < 1200; ++i) {  // 3 s start-up at 400 Hz, still
    s.t_s = i / 400.0;
    EXPECT_EQ(estimator.update(s).heading_deg, 0.0);
  }
  s.rate_dps = Vec3(0.1, 0.2, 9.5);  // 10 dps true rate on top of the -0.5 bias
  for (; i < 1200 + 400; ++i) {
    s.t_s = i / 400.0;
    estimator.update(s);
  }
  EXPECT_NEAR(estimator.last().bias_dps.z(), -0.5, 1e-12);
  EXPECT_NEAR(estimator.last().heading_deg, 10.0, 1e-9);
  const Eigen::Quaterniond expected(Eigen::AngleAxisd(deg_to_rad(10.0), Vec3::UnitZ()));
  EXPECT_LT(estimator.last().attitude.angularDistance(expected), 1e-9);
}
