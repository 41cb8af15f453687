#include <gtest/gtest.h>

#include <chrono>
#include <string>
#include <thread>
#include <vector>

#include "io/csv_replay.hpp"
#include "pipeline/read_ahead.hpp"
#include "temp_dir.hpp"

using headingd::core::Sample;
using headingd::drivers::CsvReplaySource;
using headingd::drivers::InputError;
using headingd::pipeline::ReadAheadSource;
using headingd::test::TempDir;

namespace {

std::string recording(int lines, int bad_line) {
  std::string text = "time_s,gx_dps,gy_dps,gz_dps,temp_c\n";
  for (int i = 0; i < lines; ++i) {
    if (i == bad_line) {
      text += "oops\n";
      continue;
    }
    text += std::to_string(0.0025 * i) + ",0.1," + std::to_string(i) + ",-0.5,25\n";
  }
  return text;
}

struct Read {
  std::vector<Sample> samples;
  std::string error;  // empty when the source ended cleanly
};

// Reads in batches of `batch` until the end or an InputError, by read() and next() (a view,
// as the pipeline reads) in turn.
Read read_all(headingd::core::SampleSource& source, std::size_t batch) {
  Read out;
  std::vector<Sample> buffer(batch);
  try {
    for (bool by_view = false;; by_view = !by_view) {
      const std::span<const Sample> got =
          by_view ? source.next(buffer) : std::span<const Sample>(buffer).first(source.read(buffer));
      if (got.empty()) break;
      out.samples.insert(out.samples.end(), got.begin(), got.end());
    }
  } catch (const InputError& error) {
    out.error = error.what();
  }
  return out;
}

}  // namespace

// Through the ring (blocks smaller and larger than the reader's batches, the ring as small as
// it gets), the samples and the error after them are exactly what the file gives directly.
TEST(ReadAhead, DeliversWhatTheSourceGivesThenItsErrorUnchanged) {
  TempDir dir;
  for (const int bad : {-1, 0, 1, 500, 999}) {
    const std::string path = dir.file("r.csv", recording(1000, bad));
    CsvReplaySource direct_source(path);
    const Read direct = read_all(direct_source, 7);
    for (const std::size_t block : {1u, 3u, 64u, 4096u}) {
      for (const std::size_t batch : {1u, 5u, 4096u}) {
        CsvReplaySource inner(path);
        ReadAheadSource ahead(
            inner, [&inner] { return inner.fraction_read(); }, block, 2);
        const Read through = read_all(ahead, batch);
        ASSERT_EQ(through.samples.size(), direct.samples.size()) << "bad line " << bad << ", block " << block;
        for (std::size_t i = 0; i < direct.samples.size(); ++i) {
          ASSERT_EQ(through.samples[i].t_s, direct.samples[i].t_s);
          ASSERT_EQ(through.samples[i].rate_dps, direct.samples[i].rate_dps);
        }
        EXPECT_EQ(through.error, direct.error);
        EXPECT_EQ(ahead.health().samples, direct_source.health().samples);
        if (bad < 0) {
          ASSERT_TRUE(ahead.fraction_read().has_value());
          EXPECT_DOUBLE_EQ(*ahead.fraction_read(), 1.0);
        }
        EXPECT_EQ(ahead.read(std::span<Sample>()), 0u);
      }
    }
    if (bad >= 0) {
      EXPECT_NE(direct.error.find("r.csv:" + std::to_string(bad + 2) + ": expected 5 fields"), std::string::npos)
          << direct.error;
    }
  }
}

// Closing with the reader waiting for room (the ring full, nothing taken) ends it at once,
// and reads after close return nothing.
TEST(ReadAhead, CloseWhileTheReaderWaitsForRoom) {
  TempDir dir;
  const std::string path = dir.file("r.csv", recording(20000, -1));
  CsvReplaySource inner(path);
  ReadAheadSource ahead(inner, {}, 16, 2);
  std::vector<Sample> one(1);
  ASSERT_EQ(ahead.read(one), 1u);  // starts the reader, which soon fills both blocks
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  const auto start = std::chrono::steady_clock::now();
  ahead.close();
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(1));
  EXPECT_EQ(ahead.read(one), 0u);
}
