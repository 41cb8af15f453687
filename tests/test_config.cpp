#include <gtest/gtest.h>

#include "service/config_file.hpp"
#include "temp_dir.hpp"

using headingd::app::ConfigError;
using headingd::app::load_config;
using headingd::app::parse_config;
using headingd::core::Method;

namespace {

std::string error_of(const std::string& text) {
  try {
    parse_config(text, "test.toml");
  } catch (const ConfigError& error) {
    return error.what();
  }
  ADD_FAILURE() << "accepted: " << text;
  return {};
}

}  // namespace

TEST(Config, ReadsEveryEstimatorKey) {
  const auto config = parse_config(R"(
[estimator]
method = "b"
segment_s = 2.5
k_range = 6
k_mean = 1.5
n_means = 20
sigma_still_dps = [0.9, 0.8, 0.1]
still_at_start = false
)",
                                   "test.toml");
  EXPECT_EQ(config.estimator.method, Method::B);
  const auto& s = config.estimator.segments;
  EXPECT_DOUBLE_EQ(s.segment_s, 2.5);
  EXPECT_DOUBLE_EQ(s.k_range, 6.0);
  EXPECT_DOUBLE_EQ(s.k_mean, 1.5);
  EXPECT_EQ(s.n_means, 20u);
  ASSERT_TRUE(s.sigma_still_dps.has_value());
  EXPECT_DOUBLE_EQ(s.sigma_still_dps->z(), 0.1);
  EXPECT_FALSE(s.still_at_start);
}

TEST(Config, ReadsAutoAndTemperatureTables) {
  const auto config = parse_config(R"(
[estimator]
method = "auto"
[estimator.auto]
min_segment_s = 0.5
k_range = 12
k_mean = 4
arw_dps_rt_hz = [0.1, 0.1, 0.011]
bias_walk_dps_rt_s = 0.0002
block_s = 0.05
scale_factor_sigma = 0.003
calibrate_sigma = false
retract_before_creep = false
recover_after_s = 30
zero_rate_sigma_dps = 20
restart_bias_sigma_dps = 0.05
[estimator.temperature]
enabled = false
reference_c = 30
half_life_h = 2
min_span_c = 3
quadratic_span_c = 20
min_points = 5
unmodelled_dps_per_c = 0.01
)",
                                   "test.toml");
  const auto& a = config.estimator.automatic;
  EXPECT_EQ(config.estimator.method, Method::Auto);
  EXPECT_DOUBLE_EQ(a.min_segment_s, 0.5);
  EXPECT_DOUBLE_EQ(a.k_range, 12.0);
  EXPECT_DOUBLE_EQ(a.k_mean, 4.0);
  ASSERT_TRUE(a.arw_dps_rt_hz.has_value());
  EXPECT_DOUBLE_EQ(a.arw_dps_rt_hz->z(), 0.011);
  EXPECT_DOUBLE_EQ(a.bias_walk_dps_rt_s, 0.0002);
  EXPECT_DOUBLE_EQ(a.block_s, 0.05);
  EXPECT_DOUBLE_EQ(a.scale_factor_sigma, 0.003);
  EXPECT_FALSE(a.calibrate_sigma);
  EXPECT_FALSE(a.retract_before_creep);
  EXPECT_DOUBLE_EQ(a.recover_after_s, 30.0);
  EXPECT_DOUBLE_EQ(a.zero_rate_sigma_dps, 20.0);
  EXPECT_DOUBLE_EQ(a.restart_bias_sigma_dps, 0.05);
  EXPECT_FALSE(a.use_temperature);
  EXPECT_DOUBLE_EQ(a.temperature.reference_c, 30.0);
  EXPECT_DOUBLE_EQ(a.temperature.half_life_s, 7200.0);
  EXPECT_EQ(a.temperature.min_points, 5u);
  EXPECT_DOUBLE_EQ(a.unmodelled_bias_per_c_dps, 0.01);
  EXPECT_NE(error_of("[estimator.temperature]\nunmodelled_dps_per_c = -0.1\n").find("allowed [0, 1]"),
            std::string::npos);
  EXPECT_NE(error_of("[estimator.auto]\nk_men = 3\n").find("'estimator.auto.k_men' is not a known key"),
            std::string::npos);
  EXPECT_NE(error_of("[estimator.auto]\nscale_factor_sigma = 2\n").find("allowed [0, 0.5]"), std::string::npos);
  EXPECT_NE(error_of("[estimator.auto]\nzero_rate_sigma_dps = 0\n").find("allowed (0, 100]"), std::string::npos);
  EXPECT_NE(error_of("[estimator.auto]\nrestart_bias_sigma_dps = 11\n").find("allowed [0, 10]"), std::string::npos);
}

TEST(Config, EmptyFileKeepsDefaults) {
  const auto config = parse_config("", "test.toml");
  EXPECT_EQ(config.estimator.method, Method::Auto);
  EXPECT_DOUBLE_EQ(config.estimator.segments.k_range, 7.0);
  EXPECT_DOUBLE_EQ(config.estimator.automatic.k_mean, 3.5);
}

TEST(Config, WrongTypeNamesKeyLineAndValue) {
  const auto message = error_of("[estimator]\n\nk_range = \"seven\"\n");
  EXPECT_NE(message.find("test.toml:3:"), std::string::npos) << message;
  EXPECT_NE(message.find("'estimator.k_range' must be a number, found a string 'seven'"), std::string::npos) << message;
}

TEST(Config, OutOfRangeNamesAllowedRange) {
  const auto message = error_of("[estimator]\nsegment_s = -3\n");
  EXPECT_NE(message.find("test.toml:2:"), std::string::npos) << message;
  EXPECT_NE(message.find("'estimator.segment_s' is -3, allowed (0, 600]"), std::string::npos) << message;
  EXPECT_NE(error_of("[estimator]\nn_means = 1000\n").find("allowed [1, 64]"), std::string::npos);
  EXPECT_NE(error_of("[estimator]\nmethod = \"z\"\n").find("allowed \"auto\", \"a\", \"b\" or \"c\""),
            std::string::npos);
}

TEST(Config, UnknownKeyAndSectionRejected) {
  auto message = error_of("[estimator]\nk_rang = 7\n");
  EXPECT_NE(message.find("test.toml:2:"), std::string::npos) << message;
  EXPECT_NE(message.find("'estimator.k_rang' is not a known key"), std::string::npos) << message;
  message = error_of("[estimatr]\n");
  EXPECT_NE(message.find("'estimatr' is not a known section"), std::string::npos) << message;
}

TEST(Config, DiscoveryServerMustBeNumericAddressAndPort) {
  auto message = error_of("[dds]\ndiscovery_server = \"server.local:11811\"\n");
  EXPECT_NE(message.find("test.toml:2:"), std::string::npos) << message;
  EXPECT_NE(message.find("'server.local' is not a numeric IPv4 address"), std::string::npos) << message;
  message = error_of("[dds]\ndiscovery_server = \"127.0.0.1:70000\"\n");
  EXPECT_NE(message.find("port '70000' is not a number in [1, 65535]"), std::string::npos) << message;
  message = error_of("[dds]\ndiscovery_server = \"127.0.0.1\"\n");
  EXPECT_NE(message.find("must be IPV4:PORT"), std::string::npos) << message;
  EXPECT_NE(error_of("[dds]\ndiscovery_server = \"127.0.0.1:\"\n").find("port ''"), std::string::npos);
  message = error_of("[dds]\ndiscovery_server = [\"\", \"10.0.0.2:x\"]\n");
  EXPECT_NE(message.find("port 'x'"), std::string::npos) << message;
  EXPECT_NE(error_of("[dds]\ndiscovery_server = [\"\"]\n").find("names no server"), std::string::npos);
  EXPECT_NE(error_of("[dds]\ndiscovery_server = [7]\n").find("must be a string"), std::string::npos);
}

TEST(Config, DiscoveryServersByPositionAsServerId) {
  EXPECT_EQ(parse_config("[dds]\ndiscovery_server = \"10.0.0.1:11811\"\n", "t").dds.discovery_servers,
            (std::vector<std::string>{"10.0.0.1:11811"}));
  // As in ROS_DISCOVERY_SERVER: the position is the id given to `fastdds discovery -i`.
  EXPECT_EQ(parse_config("[dds]\ndiscovery_server = [\"\", \"10.0.0.2:11812\"]\n", "t").dds.discovery_servers,
            (std::vector<std::string>{"", "10.0.0.2:11812"}));
}

TEST(Config, SyntaxErrorHasPosition) {
  const auto message = error_of("[estimator\n");
  EXPECT_EQ(message.rfind("test.toml:1:", 0), 0u) << message;
}

TEST(Config, MissingFileSaysSo) {
  try {
    load_config("/nonexistent/headingd.toml");
    FAIL();
  } catch (const ConfigError& error) {
    EXPECT_NE(std::string(error.what()).find("cannot open config /nonexistent/headingd.toml"), std::string::npos);
  }
}

TEST(Config, ReadsTheIioSensor) {
  const auto config = parse_config(R"(
[sensor]
kind = "iio"
[sensor.iio]
device = "st,l3gd20h-gyro"
trigger = "headingd"
sampling_frequency_hz = 400
buffer_length = 512
watermark = 8
mount_matrix = "0, 1, 0; 1, 0, 0; 0, 0, -1"
root = "/tmp/fake"
give_up_s = 5
)",
                                   "test.toml");
  const auto& iio = config.sensor.iio;
  EXPECT_EQ(config.sensor.kind, "iio");
  EXPECT_EQ(iio.device, "st,l3gd20h-gyro");
  EXPECT_EQ(iio.trigger, "headingd");
  EXPECT_EQ(iio.sampling_frequency_hz, 400.0);
  EXPECT_EQ(iio.buffer_length, 512);
  EXPECT_EQ(iio.watermark, 8);
  ASSERT_TRUE(iio.mount);
  EXPECT_EQ((*iio.mount)(0, 1), 1.0);
  EXPECT_EQ((*iio.mount)(2, 2), -1.0);
  EXPECT_EQ(iio.root, "/tmp/fake");
  EXPECT_EQ(iio.give_up_s, 5.0);
  // The defaults: our own L3GD20H driver; the IIO source wakes every 7 scans (18.4 ms at 380 Hz).
  EXPECT_EQ(parse_config("", "test.toml").sensor.kind, "l3gd20h");
  EXPECT_EQ(parse_config("", "test.toml").sensor.iio.watermark, 7);
}

TEST(Config, IioMistakesNameTheKey) {
  EXPECT_NE(
      error_of("[sensor.iio]\nmount_matrix = \"1, 0, 0; 0, 1, 0\"\n")
          .find("'sensor.iio.mount_matrix' is '1, 0, 0; 0, 1, 0', expected \"x0, x1, x2; y0, y1, y2; z0, z1, z2\""),
      std::string::npos)
      << error_of("[sensor.iio]\nmount_matrix = \"1, 0, 0; 0, 1, 0\"\n");
  EXPECT_NE(error_of("[sensor.iio]\nbuffer_length = 8\nwatermark = 16\n")
                .find("sensor.iio.watermark (16) must not exceed sensor.iio.buffer_length (8)"),
            std::string::npos);
  EXPECT_NE(error_of("[sensor.iio]\nbus = \"/dev/i2c-1\"\n").find("'sensor.iio.bus' is not a known key"),
            std::string::npos);
  EXPECT_NE(error_of("[sensor.iio]\nsampling_frequency_hz = -1\n").find("sensor.iio.sampling_frequency_hz"),
            std::string::npos);
}

TEST(Config, ReadsTheRollingRecording) {
  const auto config =
      parse_config("[record]\ndir = \"/var/lib/headingd/rec\"\nsplit_hours = 2\nkeep_hours = 72\n", "t");
  EXPECT_EQ(config.record_dir, "/var/lib/headingd/rec");
  EXPECT_DOUBLE_EQ(config.record_split_hours, 2.0);
  EXPECT_DOUBLE_EQ(config.record_keep_hours, 72.0);
  EXPECT_EQ(parse_config("", "t").record_dir, "") << "none unless asked for";
  EXPECT_NE(error_of("[record]\nsplit_hours = 0\n").find("'record.split_hours' is 0, allowed [0.001, 168]"),
            std::string::npos);
  EXPECT_NE(error_of("[record]\nkeep = 3\n").find("dir, split_hours, keep_hours"), std::string::npos);
}
