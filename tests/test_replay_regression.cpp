// Recorded-log regressions (gpsd's regress-driver idea): each recording under tests/data/
// is replayed and its estimates compared with the reviewed expected output next to it.
// Regenerating expected output is an explicit step: scripts/regress-update.sh.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include "app/replay_command.hpp"
#include "io/text_fields.hpp"
#include "temp_dir.hpp"

using headingd::test::TempDir;

namespace {

std::vector<std::string> lines_of(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// Numbers may differ in the last printed digit between compilers; anything more is a change.
void expect_same_estimates(const std::string& expected_path, const std::string& actual_path) {
  const auto expected = lines_of(expected_path);
  const auto actual = lines_of(actual_path);
  ASSERT_FALSE(expected.empty()) << expected_path;
  ASSERT_EQ(actual.size(), expected.size()) << "row count changed";
  ASSERT_EQ(actual[0], expected[0]) << "header changed";
  headingd::drivers::Fields want;
  headingd::drivers::Fields got;
  int reported = 0;
  for (std::size_t row = 1; row < expected.size() && reported < 10; ++row) {
    headingd::drivers::split_fields(expected[row], ',', want);
    headingd::drivers::split_fields(actual[row], ',', got);
    ASSERT_EQ(got.count, want.count) << "row " << row;
    for (std::size_t i = 0; i < want.count; ++i) {
      if (want.items[i] == got.items[i]) continue;
      const auto a = headingd::drivers::parse_double(want.items[i]);
      const auto b = headingd::drivers::parse_double(got.items[i]);
      if (a && b && std::abs(*a - *b) <= 2e-6) continue;
      ADD_FAILURE() << "row " << row << " column " << i + 1 << ": expected " << want.items[i] << ", got "
                    << got.items[i];
      ++reported;
    }
  }
}

void check_recording(const std::string& name, const std::string& method) {
  const std::string dir = HEADINGD_SOURCE_DIR "/tests/data/" + name;
  TempDir tmp;
  headingd::app::ReplayOptions options;
  options.input = dir + "/imu.csv";
  options.method = method;
  options.output = tmp.path("estimates.csv");
  options.quiet = true;
  ASSERT_EQ(headingd::app::run_replay(options), 0);
  expect_same_estimates(dir + "/expected-" + method + ".csv", options.output);
}

}  // namespace

TEST(RecordedRegression, AgvMinuteMethodA) { check_recording("agv-1min", "a"); }
TEST(RecordedRegression, AgvMinuteMethodB) { check_recording("agv-1min", "b"); }
TEST(RecordedRegression, AgvMinuteMethodC) { check_recording("agv-1min", "c"); }
TEST(RecordedRegression, AgvMinuteMethodAuto) { check_recording("agv-1min", "auto"); }
TEST(RecordedRegression, BroadExcerptMethodC) { check_recording("broad-05-excerpt", "c"); }
TEST(RecordedRegression, BroadExcerptMethodAuto) { check_recording("broad-05-excerpt", "auto"); }
