#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "io/companion_file.hpp"
#include "io/csv_header.hpp"
#include "io/csv_replay.hpp"
#include "io/joined_replay.hpp"
#include "io/text_fields.hpp"
#include "temp_dir.hpp"

using headingd::core::Sample;
using headingd::drivers::CsvReplaySource;
using headingd::drivers::InputError;
using headingd::drivers::JoinedReplaySource;
using headingd::drivers::OpenError;
using headingd::test::TempDir;

namespace {

template <typename Source>
std::vector<Sample> read_all(Source& source) {
  std::vector<Sample> all;
  std::vector<Sample> batch(3);  // small batches exercise the hand-over between calls
  while (const auto n = source.read(batch)) all.insert(all.end(), batch.begin(), batch.begin() + static_cast<long>(n));
  return all;
}

// Reads until the error and returns its message; fails the test if none comes.
std::string error_of(const std::string& path, std::size_t* good_samples = nullptr) {
  std::vector<Sample> batch(4096);
  std::size_t good = 0;
  try {
    CsvReplaySource source(path);
    while (const auto n = source.read(batch)) good += n;
  } catch (const InputError& error) {
    if (good_samples) *good_samples = good;
    return error.what();
  }
  ADD_FAILURE() << "no error for " << path;
  return {};
}

}  // namespace

TEST(CsvReplay, NativeWithCommentsTemperatureAndAnyColumnOrder) {
  TempDir dir;
  const auto path = dir.file("rec.csv",
                             "# sensor: L3GD20H\n# rate: 400 Hz\n"
                             "temp_c,time_s,gz_dps,gx_dps,extra,gy_dps\n"
                             "25.5,0.0,-0.455,0.1,x,0.2\n"
                             "\n"
                             "25.5,0.0025,+1.5,0.1,y,0.2\r\n"
                             "25.6,0.005,2e-3,0.1,z,0.2\n");
  CsvReplaySource source(path);
  EXPECT_EQ(source.format(), CsvReplaySource::Format::Native);
  EXPECT_TRUE(source.has_temperature());
  ASSERT_EQ(source.comments().size(), 2u);
  EXPECT_EQ(source.comments()[0], "sensor: L3GD20H");
  const auto samples = read_all(source);
  ASSERT_EQ(samples.size(), 3u);
  EXPECT_DOUBLE_EQ(samples[0].rate_dps.z(), -0.455);
  EXPECT_DOUBLE_EQ(samples[1].rate_dps.z(), 1.5);
  EXPECT_DOUBLE_EQ(samples[2].rate_dps.z(), 0.002);
  EXPECT_DOUBLE_EQ(samples[2].t_s, 0.005);
  EXPECT_DOUBLE_EQ(samples[2].temp_c, 25.6);
  EXPECT_DOUBLE_EQ(samples[1].rate_dps.y(), 0.2);
}

TEST(CsvReplay, WithoutTemperatureColumnGivesNaN) {
  TempDir dir;
  CsvReplaySource source(dir.file("r.csv", "time_s,gx_dps,gy_dps,gz_dps\n0,1,2,3\n"));
  EXPECT_FALSE(source.has_temperature());
  const auto samples = read_all(source);
  ASSERT_EQ(samples.size(), 1u);
  EXPECT_TRUE(std::isnan(samples[0].temp_c));
}

TEST(CsvReplay, EurocConvertsNanosecondsAndRadians) {
  TempDir dir;
  const auto path = dir.file("imu.csv",
                             "#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y [rad s^-1],w_RS_S_z [rad s^-1],"
                             "a_RS_S_x [m s^-2],a_RS_S_y [m s^-2],a_RS_S_z [m s^-2]\n"
                             "1000000000,0.0,0.0,3.141592653589793,0.1,0.0,9.8\n"
                             "1003500000,0.017453292519943295,0,0,0.1,0.0,9.8\n");
  CsvReplaySource source(path);
  EXPECT_EQ(source.format(), CsvReplaySource::Format::Euroc);
  const auto samples = read_all(source);
  ASSERT_EQ(samples.size(), 2u);
  EXPECT_DOUBLE_EQ(samples[0].t_s, 1.0);
  EXPECT_DOUBLE_EQ(samples[1].t_s, 1.0035);
  EXPECT_NEAR(samples[0].rate_dps.z(), 180.0, 1e-12);
  EXPECT_NEAR(samples[1].rate_dps.x(), 1.0, 1e-12);
}

// The replay, the companion-file test and score's tables all find the header through
// read_header_line: a comment that only mentions "timestamp" is a comment, EuRoC's is a header.
TEST(CsvHeader, CommentsBeforeAnEurocHeaderAndUnitsLeftOut) {
  TempDir dir;
  const auto path = dir.file("gt.csv",
                             "# exported 2024\n\n#  timestamps below in ns\n"
                             " # timestamp [ns] , q_RS_w [], p_RS_R_x [m]\n1,1,0\n");
  headingd::drivers::LineReader lines(path);
  std::vector<std::string> comments;
  const auto header = headingd::drivers::read_header_line(lines, &comments);
  ASSERT_TRUE(header);
  EXPECT_TRUE(header->euroc);
  EXPECT_EQ(header->text, "timestamp [ns] , q_RS_w [], p_RS_R_x [m]");
  EXPECT_EQ(comments, (std::vector<std::string>{"exported 2024", "timestamps below in ns"}));
  EXPECT_EQ(headingd::drivers::column_name(" q_RS_w [] "), "q_RS_w");
  EXPECT_EQ(headingd::drivers::column_name("gz_dps"), "gz_dps");
  EXPECT_EQ(headingd::drivers::companion_kind(path), "an EuRoC/ASL ground truth");

  // A native header after comments; a file of comments only has none.
  const auto native = dir.file("imu.csv", "#timestamp-free note\ntime_s,gx_dps,gy_dps,gz_dps\n0,0,0,0\n");
  headingd::drivers::LineReader native_lines(native);
  const auto native_header = headingd::drivers::read_header_line(native_lines);
  ASSERT_TRUE(native_header);
  EXPECT_FALSE(native_header->euroc);
  EXPECT_EQ(native_header->text, "time_s,gx_dps,gy_dps,gz_dps");
  EXPECT_EQ(headingd::drivers::companion_kind(native), std::nullopt);
  headingd::drivers::LineReader empty_lines(dir.file("c.csv", "# nothing\n\n"));
  EXPECT_FALSE(headingd::drivers::read_header_line(empty_lines));
  EXPECT_EQ(headingd::drivers::companion_kind(dir.file("t.csv", "time_s,heading_deg,moving\n")), "a truth file");
}

// Parts of one recording replay as the whole; a part that does not go on in time is an
// InputError naming it after every sample before it; a damaged part is named and passed.
TEST(JoinedReplay, PartsInOrderThenOneOutOfTimeThenOneMissing) {
  TempDir dir;
  const std::string header = "time_s,gx_dps,gy_dps,gz_dps\n";
  const auto a = dir.file("a.csv", header + "0.0,0,0,1\n0.5,0,0,2\n");
  const auto b_plain = dir.file("b.csv",
                                "#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y [rad s^-1],w_RS_S_z [rad s^-1]\n"
                                "1000000000,0,0,0.017453292519943295\n");
  const auto c = dir.file("c.csv", header + "# a comment between\n1.5,0,0,4\n");
  {
    JoinedReplaySource joined({a, b_plain, c});
    const auto all = read_all(joined);
    ASSERT_EQ(all.size(), 4u);
    EXPECT_DOUBLE_EQ(all[2].t_s, 1.0);
    EXPECT_NEAR(all[2].rate_dps.z(), 1.0, 1e-12) << "each part read in its own format";
    EXPECT_DOUBLE_EQ(all[3].rate_dps.z(), 4.0);
    EXPECT_EQ(joined.health().samples, 4u);
    EXPECT_DOUBLE_EQ(joined.health().rate_hz, 2.0);
    EXPECT_EQ(joined.fraction_read(), 1.0);
    EXPECT_NE(joined.describe().find("3 recordings joined"), std::string::npos) << joined.describe();
    EXPECT_TRUE(joined.run_boundaries().empty());
  }
  {
    // The recorder's end-of-run line closing a file: the next one is another run.
    const auto ended =
        dir.file("ended.csv", header + "0.0,0,0,1\n0.5,0,0,2\n# measured output rate 2.000 Hz; 2 samples, 0 lost\n");
    const auto split = dir.file("split.csv", header + "2.0,0,0,1\n# continued in later.csv\n");
    const auto later = dir.file("later.csv", header + "2.5,0,0,1\n");
    JoinedReplaySource joined({ended, split, later});
    EXPECT_EQ(read_all(joined).size(), 4u);
    ASSERT_EQ(joined.run_boundaries().size(), 1u);
    EXPECT_EQ(joined.run_boundaries()[0].file, split);
    EXPECT_DOUBLE_EQ(joined.run_boundaries()[0].gap_s, 1.5);
  }
  std::vector<Sample> batch(16);
  {
    JoinedReplaySource joined({a, c, b_plain});  // b goes back to t = 1.0 after c's 1.5
    std::size_t good = 0;
    try {
      while (const auto n = joined.read(batch)) good += n;
      ADD_FAILURE() << "no error";
    } catch (const InputError& error) {
      EXPECT_EQ(error.file(), b_plain);
      EXPECT_NE(error.problem().find("is not after the last of " + c), std::string::npos) << error.what();
    }
    EXPECT_EQ(good, 3u);
  }
  {
    // Damaged parts inside the series (one cut short, one gone, one with a broken header) are
    // named; what they held before the damage is replayed and so is every part after them.
    const auto cut = dir.file("cut.csv", header + "0.7,0,0,5\n0.8,0,0,5\n0.9,0,0");
    const auto broken = dir.file("broken.csv", "tme_s,gx\n1.1,0\n");
    JoinedReplaySource joined({a, cut, dir.path("gone.csv"), broken, c});
    const auto all = read_all(joined);
    ASSERT_EQ(all.size(), 5u) << "a's 2, cut's 2 whole lines, c's 1";
    EXPECT_DOUBLE_EQ(all[3].t_s, 0.8);
    EXPECT_DOUBLE_EQ(all[4].t_s, 1.5);
    ASSERT_EQ(joined.damaged_parts().size(), 3u);
    EXPECT_EQ(joined.damaged_parts()[0].file, cut);
    EXPECT_NE(joined.damaged_parts()[0].error.find("truncated"), std::string::npos) << joined.damaged_parts()[0].error;
    EXPECT_EQ(joined.damaged_parts()[1].file, dir.path("gone.csv"));
    EXPECT_EQ(joined.damaged_parts()[2].file, broken);
  }
  {
    // The last part's error ends the replay as a single recording's does, after its good samples.
    JoinedReplaySource joined({a, dir.file("cut_last.csv", header + "0.7,0,0,5\n0.8,0,0")});
    std::size_t good = 0;
    EXPECT_THROW(
        {
          while (const auto n = joined.read(batch)) good += n;
        },
        InputError);
    EXPECT_EQ(good, 3u);
  }
}

// A rolling series' files name their run: the runs are told apart where time cannot tell them
// (a crash, then a restart on the same boot: the clock goes on), and one run's files stay one run
// across a file lost to a full disk; a run's clock that goes back is out of order, not a reboot.
TEST(JoinedReplay, FilesThatNameTheirRunAreSplitByIt) {
  TempDir dir;
  const auto part = [&](const std::string& name, const std::string& run, const std::string& lines) {
    return dir.file(
        name, "# sensor: hand-made\n# rolling series run " + run + ", file 1\ntime_s,gx_dps,gy_dps,gz_dps\n" + lines);
  };
  const auto crashed = part("r1.csv", "headingd-r1", "0.0,0,0,1\n0.5,0,0,2\n0.9,0,0");  // cut short
  const auto restarted = part("r2.csv", "headingd-r2", "5.0,0,0,3\n5.5,0,0,4\n# continued in r2b.csv\n");
  const auto lost = part("r2b.csv", "headingd-r2", "6.0,0,0,5\n6.");  // a full disk
  const auto resumed = part("r2c.csv", "headingd-r2", "9.0,0,0,6\n");
  const auto position = headingd::drivers::series_position(lost);
  ASSERT_TRUE(position.has_value());
  EXPECT_EQ(position->run, "headingd-r2");
  EXPECT_EQ(position->file, 1);
  EXPECT_FALSE(headingd::drivers::series_position(dir.file("plain.csv", "time_s,gx_dps,gy_dps,gz_dps\n0,0,0,0\n")));
  EXPECT_FALSE(headingd::drivers::series_position(dir.path("missing.csv")));
  std::vector<Sample> batch(16);
  {
    JoinedReplaySource joined({crashed, restarted, lost, resumed}, true);
    EXPECT_EQ(read_all(joined).size(), 2u) << "run 1 ends at its crash though the clock goes on";
    ASSERT_EQ(joined.damaged_parts().size(), 1u);
    EXPECT_EQ(joined.damaged_parts()[0].file, crashed);
    ASSERT_TRUE(joined.next_run());
    EXPECT_EQ(joined.current_file(), restarted);
    const auto run2 = read_all(joined);
    ASSERT_EQ(run2.size(), 4u) << "run 2 goes on over its lost file";
    EXPECT_DOUBLE_EQ(run2.back().t_s, 9.0);
    EXPECT_EQ(joined.damaged_parts().size(), 1u);
    EXPECT_FALSE(joined.next_run());
  }
  {
    JoinedReplaySource joined({crashed, restarted}, false);  // one replay: the restart carried on, named
    EXPECT_EQ(read_all(joined).size(), 4u);
    ASSERT_EQ(joined.run_boundaries().size(), 1u);
    EXPECT_EQ(joined.run_boundaries()[0].file, restarted);
  }
  {
    const auto back = part("r2d.csv", "headingd-r2", "2.0,0,0,7\n");  // run 2's clock going back
    JoinedReplaySource joined({restarted, lost, back}, true);
    EXPECT_THROW(
        {
          while (joined.read(batch) > 0) {
          }
        },
        InputError);
  }
}

TEST(CsvReplay, SharedBroadRecordingReadsCompletely) {
  const std::string path = HEADINGD_SOURCE_DIR "/../shared/data/broad-05/imu.csv";
  if (!std::ifstream(path)) GTEST_SKIP() << "shared data not beside the checkout";
  CsvReplaySource source(path);
  const auto samples = read_all(source);
  EXPECT_EQ(samples.size(), 59212u);
  EXPECT_NEAR(samples.back().t_s - samples.front().t_s, 207.2, 0.1);
}

TEST(CsvReplayErrors, MalformedLineNamesFileLineAndCount) {
  TempDir dir;
  const auto path = dir.file("bad.csv", "# c\ntime_s,gx_dps,gy_dps,gz_dps\n0,1,2,3\n0.1,1,2\n");
  std::size_t good = 0;
  const auto message = error_of(path, &good);
  EXPECT_NE(message.find(path + ":4: expected 4 fields, found 3"), std::string::npos) << message;
  EXPECT_EQ(good, 1u) << "the good sample before the bad line is delivered";
}

TEST(CsvReplayErrors, NonNumericFieldNamesColumn) {
  TempDir dir;
  const auto path = dir.file("bad.csv", "time_s,gx_dps,gy_dps,gz_dps\n0,1,2,3\n0.1,1,abc,3\n");
  const auto message = error_of(path);
  EXPECT_NE(message.find(":3: field 'gy_dps' (column 3): 'abc' is not a finite number"), std::string::npos) << message;
  EXPECT_NE(error_of(dir.file("nan.csv", "time_s,gx_dps,gy_dps,gz_dps\n0,nan,2,3\n")).find("gx_dps"),
            std::string::npos);
}

TEST(CsvReplayErrors, MissingColumnListsWhatWasFound) {
  TempDir dir;
  const auto message = error_of(dir.file("bad.csv", "time_s,gx_dps,gy_dps\n0,1,2\n"));
  EXPECT_NE(message.find(":1: missing column 'gz_dps' in header (found: time_s,gx_dps,gy_dps)"), std::string::npos)
      << message;
}

TEST(CsvReplayErrors, TimeGoingBackwardsOrStanding) {
  TempDir dir;
  auto message = error_of(dir.file("back.csv", "time_s,gx_dps,gy_dps,gz_dps\n1.0,0,0,0\n0.5,0,0,0\n"));
  EXPECT_NE(message.find(":3: time goes backwards"), std::string::npos) << message;
  message = error_of(dir.file("same.csv", "time_s,gx_dps,gy_dps,gz_dps\n1.0,0,0,0\n1.0,0,0,0\n"));
  EXPECT_NE(message.find(":3: time does not advance"), std::string::npos) << message;
}

TEST(CsvReplayErrors, EmptyFileHeaderOnlyAndNoHeader) {
  TempDir dir;
  EXPECT_NE(error_of(dir.file("empty.csv", "")).find("file is empty"), std::string::npos);
  EXPECT_NE(error_of(dir.file("hdr.csv", "time_s,gx_dps,gy_dps,gz_dps\n")).find("no samples after the header"),
            std::string::npos);
  EXPECT_NE(error_of(dir.file("com.csv", "# only a comment\n")).find("no header line"), std::string::npos);
}

TEST(CsvReplayErrors, EurocBadTimestamp) {
  TempDir dir;
  const auto message = error_of(dir.file("e.csv",
                                         "#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y [rad s^-1],w_RS_S_z [rad s^-1]\n"
                                         "1.5e9,0,0,0\n"));
  EXPECT_NE(message.find(":2: field 'timestamp [ns]' (column 1): '1.5e9' is not an integer"), std::string::npos)
      << message;
}

TEST(CsvReplayErrors, MissingFileIsAnOpenError) { EXPECT_THROW(CsvReplaySource("/nonexistent/imu.csv"), OpenError); }

TEST(CsvReplay, TruncatedLastLineIsAnError) {
  // A file cut short, or still being written: the last line may be half a number.
  TempDir dir;
  const auto path = dir.file("rec.csv", "time_s,gx_dps,gy_dps,gz_dps\n0,1,2,3\n0.0025,1,2,3.14");
  CsvReplaySource source(path);
  std::vector<headingd::core::Sample> batch(8);
  EXPECT_EQ(source.read(batch), 1u);
  try {
    source.read(batch);
    FAIL() << "accepted a last line without its newline";
  } catch (const headingd::drivers::InputError& error) {
    EXPECT_EQ(error.line(), 3u);
    EXPECT_NE(error.problem().find("no newline"), std::string::npos) << error.what();
  }
}

// The one-pass scan takes plain decimals without from_chars (Clinger's fast path); whatever
// the text, the value must be from_chars' to the bit, and the same texts refused.
TEST(CsvReplay, ScannedNumbersEqualFromCharsBitForBit) {
  std::mt19937_64 random(7);
  std::vector<std::string> texts = {"0",
                                    "-0",
                                    "-0.000",
                                    "22.00",
                                    "0.035000",
                                    "-0.46375",
                                    "1e-3",
                                    "2E5",
                                    "123456789012345678",
                                    "9007199254740993",
                                    "0.1234567890123456789",
                                    "1.",
                                    ".5",
                                    "-",
                                    "+-1",
                                    "1.5.3",
                                    "inf",
                                    "nan",
                                    "0x10",
                                    "00012.5000",
                                    "1e400",
                                    ""};
  // What recordings hold: doubles as their shortest round-trip text (often 17 digits, beyond
  // 2^53: the double-double path), in fixed notation as CsvOut writes them.
  std::uniform_real_distribution<double> rate(-300.0, 300.0);
  std::uniform_int_distribution<int> scale(-6, 5);
  for (int i = 0; i < 200000; ++i) {
    char text[64];
    const double value = rate(random) * std::pow(10.0, scale(random));
    const auto [end, error] = std::to_chars(text, text + sizeof text, value, std::chars_format::fixed);
    ASSERT_EQ(error, std::errc{});
    texts.emplace_back(text, end);
  }
  for (int i = 0; i < 200000; ++i) {
    const auto digits = std::uniform_int_distribution<int>(1, 20)(random);
    const auto point = std::uniform_int_distribution<int>(0, digits)(random);
    std::string text = (random() & 1) ? "-" : "";
    for (int d = 0; d < digits; ++d) {
      if (d == point && d > 0) text += '.';
      text += static_cast<char>('0' + random() % 10);
    }
    texts.push_back(text);
  }
  // The hard cases for a quotient computed to limited precision: the halfway points between two
  // neighbouring doubles, cut to 17-19 significant digits and nudged by one in the last digit.
  for (int i = 0; i < 100000; ++i) {
    const double value = std::abs(rate(random)) * std::pow(10.0, scale(random));
    const long double halfway = (static_cast<long double>(value) + std::nextafter(value, 1e300)) / 2;  // exact
    const int significant = std::uniform_int_distribution<int>(17, 19)(random);
    const int integer_digits = halfway >= 1 ? static_cast<int>(std::floor(std::log10(halfway))) + 1 : 0;
    const int decimals = std::max(1, significant - integer_digits);
    char text[96];
    std::snprintf(text, sizeof text, "%.*Lf", decimals, halfway);
    std::string cut(text);
    texts.push_back(cut);
    for (const int nudge : {-1, 1}) {
      std::string other = cut;
      char& last = other.back();
      if ((nudge < 0 && last > '0') || (nudge > 0 && last < '9')) {
        last = static_cast<char>(last + nudge);
        texts.push_back(other);
      }
    }
  }
  // Exact halfway points that fit in 19 digits: between integers 2^52..2^53 (ulp 1) at ".5",
  // between even integers above 2^53 at the odd ones, between halves below 2^52 at ".25"/".75".
  // from_chars rounds them to even; a quotient that is not exact must hand them over.
  for (int i = 0; i < 20000; ++i) {
    const std::uint64_t k = random() % (std::uint64_t{1} << 51);
    texts.push_back(std::to_string((std::uint64_t{1} << 52) + k) + ".5");
    texts.push_back(std::to_string((std::uint64_t{1} << 53) + 2 * k + 1));
    texts.push_back(std::to_string((std::uint64_t{1} << 51) + k / 2) + ((k & 1) ? ".75" : ".25"));
  }
  for (const std::string& text : texts) {
    double scanned = 0.0;
    const char* end = text.data() + text.size();
    const char* after = headingd::drivers::scan_double(text.data(), end, scanned);
    const auto reference = headingd::drivers::parse_double(text);
    if (!reference) {
      EXPECT_TRUE(after == nullptr || after != end) << text;
      continue;
    }
    ASSERT_EQ(after, end) << text;
    EXPECT_EQ(std::bit_cast<std::uint64_t>(scanned), std::bit_cast<std::uint64_t>(*reference)) << text;
  }
}
