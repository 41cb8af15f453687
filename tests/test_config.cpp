#include <gtest/gtest.h>

#include "daemon/config_file.hpp"
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
  EXPECT_DOUBLE_EQ(config.estimator.segment_s, 2.5);
  EXPECT_DOUBLE_EQ(config.estimator.k_range, 6.0);
  EXPECT_DOUBLE_EQ(config.estimator.k_mean, 1.5);
  EXPECT_EQ(config.estimator.n_means, 20u);
  ASSERT_TRUE(config.estimator.sigma_still_dps.has_value());
  EXPECT_DOUBLE_EQ(config.estimator.sigma_still_dps->z(), 0.1);
  EXPECT_FALSE(config.estimator.still_at_start);
}

TEST(Config, EmptyFileKeepsDefaults) {
  const auto config = parse_config("", "test.toml");
  EXPECT_EQ(config.estimator.method, Method::C);
  EXPECT_DOUBLE_EQ(config.estimator.k_range, 7.0);
}

TEST(Config, WrongTypeNamesKeyLineAndValue) {
  const auto message = error_of("[estimator]\n\nk_range = \"seven\"\n");
  EXPECT_NE(message.find("test.toml:3:"), std::string::npos) << message;
  EXPECT_NE(message.find("'estimator.k_range' must be a number, found a string 'seven'"), std::string::npos)
      << message;
}

TEST(Config, OutOfRangeNamesAllowedRange) {
  const auto message = error_of("[estimator]\nsegment_s = -3\n");
  EXPECT_NE(message.find("test.toml:2:"), std::string::npos) << message;
  EXPECT_NE(message.find("'estimator.segment_s' is -3, allowed (0, 600]"), std::string::npos) << message;
  EXPECT_NE(error_of("[estimator]\nn_means = 1000\n").find("allowed [1, 64]"), std::string::npos);
  EXPECT_NE(error_of("[estimator]\nmethod = \"z\"\n").find("allowed \"a\", \"b\" or \"c\""), std::string::npos);
}

TEST(Config, UnknownKeyAndSectionRejected) {
  auto message = error_of("[estimator]\nk_rang = 7\n");
  EXPECT_NE(message.find("test.toml:2:"), std::string::npos) << message;
  EXPECT_NE(message.find("'estimator.k_rang' is not a known key"), std::string::npos) << message;
  message = error_of("[estimatr]\n");
  EXPECT_NE(message.find("'estimatr' is not a known section"), std::string::npos) << message;
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
