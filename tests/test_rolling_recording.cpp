// The rolling recording (pipeline/rolling_recording_sink): files split by sample time, each a
// whole recording that replays with the samples it holds; a restart never writes over an
// earlier file; only the series' own regular files past their age are deleted (not a link
// named like one, not another file, not the file just started). The wall clock is a fake.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <random>
#include <vector>

#include "core/estimator.hpp"
#include "core/memory_source.hpp"
#include "io/csv_replay.hpp"
#include "pipeline/rolling_recording_sink.hpp"
#include "temp_dir.hpp"

namespace fs = std::filesystem;
using headingd::pipeline::rolling_file_time;
using headingd::pipeline::RollingRecordingSink;
using headingd::pipeline::RollingSettings;
using headingd::test::TempDir;

namespace {

double fake_now_s = 1796000000.0;  // 2026-11-29T…Z
double fake_wall() { return fake_now_s; }

std::vector<headingd::core::Sample> samples(double seconds, double rate_hz) {
  std::vector<headingd::core::Sample> out;
  for (int i = 0; i < static_cast<int>(seconds * rate_hz); ++i) {
    headingd::core::Sample s;
    s.t_s = 100.0 + i / rate_hz;
    s.rate_dps = {0.1, -0.2, 0.3 + 0.001 * (i % 7)};
    s.temp_c = 25.0;
    out.push_back(s);
  }
  return out;
}

std::vector<std::string> names_in(const std::string& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

std::vector<headingd::core::Sample> read_samples(const std::string& path) {
  headingd::drivers::CsvReplaySource source(path);
  std::vector<headingd::core::Sample> batch(512), all;
  while (const auto got = source.read(batch))
    all.insert(all.end(), batch.begin(), batch.begin() + static_cast<long>(got));
  return all;
}

std::size_t samples_in(const std::string& path) { return read_samples(path).size(); }

// Feeds the samples through the sink as the pipeline would, the fake clock one second on per
// 100 samples.
void feed(RollingRecordingSink& sink, const std::vector<headingd::core::Sample>& all) {
  headingd::core::Estimator estimator(headingd::core::kDefaultEstimatorSettings);
  headingd::core::MemorySource source(all);
  for (std::size_t i = 0; i < all.size(); ++i) {
    if (i % 100 == 0) fake_now_s += 1.0;
    sink.add(all[i], estimator.update(all[i]), estimator);
  }
  sink.finish(estimator, source);
}

}  // namespace

TEST(RollingRecording, NamesOfTheSeriesOnly) {
  EXPECT_EQ(*rolling_file_time("headingd-20261207T012500Z.csv.zst"), 1796606700.0);
  EXPECT_EQ(*rolling_file_time("headingd-20261207T012500Z_12.csv.zst"), 1796606700.0);
  for (const char* other : {"headingd-20261207T012500Z.csv", "headingd-20261207T012500Z-1.csv.zst",
                            "headingd-20261207T0125Z.csv.zst", "xheadingd-20261207T012500Z.csv.zst",
                            "headingd-20261207T012500Z_.csv.zst", "headingd-2026120XT012500Z.csv.zst"})
    EXPECT_FALSE(rolling_file_time(other).has_value()) << other;
}

TEST(RollingRecording, SplitsBySampleTimeAndEachFileReplays) {
  TempDir dir;
  RollingSettings settings{dir.path("rec"), 10.0 / 3600.0, 48.0};  // a file per 10 s of samples
  RollingRecordingSink sink(settings, "# sensor: hand-made\n", fake_wall);
  feed(sink, samples(25.0, 100.0));
  const auto names = names_in(settings.dir);
  ASSERT_EQ(names.size(), 3u);
  EXPECT_EQ(sink.files_started(), 3u);
  std::size_t total = 0;
  std::vector<std::size_t> counts;
  for (const auto& name : names) counts.push_back(samples_in(settings.dir + "/" + name)), total += counts.back();
  EXPECT_EQ(total, 2500u);
  EXPECT_EQ(counts, (std::vector<std::size_t>{1000, 1000, 500})) << "names sort in the order the files started";
}

TEST(RollingRecording, ARestartWritesBesideTheFileOfTheSameSecond) {
  TempDir dir;
  RollingSettings settings{dir.path("rec"), 1.0, 48.0};
  fs::create_directories(settings.dir);
  const double start_s = fake_now_s + 1.0;  // feed() moves the clock on before the first sample
  const std::string earlier = settings.dir + "/headingd-" + [&] {
    char text[32];
    const std::time_t t = static_cast<std::time_t>(start_s);
    std::tm parts{};
    gmtime_r(&t, &parts);
    std::strftime(text, sizeof text, "%Y%m%dT%H%M%SZ", &parts);
    return std::string(text);
  }() + ".csv.zst";
  std::ofstream(earlier) << "what the run before recorded";
  RollingRecordingSink sink(settings, "", fake_wall);
  feed(sink, samples(2.0, 100.0));
  std::ifstream in(earlier);
  std::string kept;
  std::getline(in, kept);
  EXPECT_EQ(kept, "what the run before recorded");
  EXPECT_EQ(names_in(settings.dir).size(), 2u);
  EXPECT_NE(sink.path().find("Z_001.csv.zst"), std::string::npos) << sink.path();
}

TEST(RollingRecording, DeletesOnlyTheSeriesOwnOldFiles) {
  TempDir dir;
  RollingSettings settings{dir.path("rec"), 1.0, 24.0};
  fs::create_directories(settings.dir);
  const auto put = [&](const std::string& name) { std::ofstream(settings.dir + "/" + name) << "x\n"; };
  put("headingd-20200101T000000Z.csv.zst");                                     // years old: deleted
  put("headingd-20200101T000000Z_3.csv.zst");                                   // the same
  put("notes-20200101T000000Z.csv.zst");                                        // not ours
  put("headingd-20200101T000000Z.csv");                                         // not ours (no .zst)
  fs::create_directories(settings.dir + "/headingd-20200102T000000Z.csv.zst");  // a directory
  const std::string outside = dir.file("precious.csv.zst", "keep me\n");
  fs::create_symlink(outside, settings.dir + "/headingd-20200103T000000Z.csv.zst");
  fake_now_s = 1796000000.0;
  put("headingd-20261129T084000Z.csv.zst");  // an hour old at the fake clock: kept
  RollingRecordingSink sink(settings, "", fake_wall);
  feed(sink, samples(1.0, 100.0));
  EXPECT_EQ(sink.files_deleted(), 2u);
  const auto names = names_in(settings.dir);
  for (const char* gone : {"headingd-20200101T000000Z.csv.zst", "headingd-20200101T000000Z_3.csv.zst"})
    EXPECT_EQ(std::count(names.begin(), names.end(), gone), 0) << gone;
  for (const char* kept :
       {"notes-20200101T000000Z.csv.zst", "headingd-20200101T000000Z.csv", "headingd-20200102T000000Z.csv.zst",
        "headingd-20200103T000000Z.csv.zst", "headingd-20261129T084000Z.csv.zst"})
    EXPECT_EQ(std::count(names.begin(), names.end(), kept), 1) << kept;
  EXPECT_TRUE(fs::exists(outside)) << "a link named like an old file: neither it nor what it points to removed";
  EXPECT_EQ(names.size(), 6u);  // the five kept and the file just started
}

// A computer without a battery-backed clock starts in the past and has its wall clock set by NTP
// mid-run, years on: the run's own files, named in the past, are aged by the sample clock and
// kept (keep 1 h; the run is 5 min long); an earlier run's file named in the past is deleted.
TEST(RollingRecording, AWallClockSetYearsOnMidRunKeepsTheRunsOwnFiles) {
  TempDir dir;
  RollingSettings settings{dir.path("rec"), 60.0 / 3600.0, 1.0};  // a file per minute, an hour kept
  fs::create_directories(settings.dir);
  std::ofstream(settings.dir + "/headingd-20000101T000000Z.csv.zst") << "x\n";  // an earlier run's
  fake_now_s = 946684900.0;                                                     // 2000-01-01T00:01:40Z
  RollingRecordingSink sink(settings, "", fake_wall);
  headingd::core::Estimator estimator(headingd::core::kDefaultEstimatorSettings);
  const auto all = samples(300.0, 100.0);
  for (std::size_t i = 0; i < all.size(); ++i) {
    fake_now_s += i == 15000 ? 26.9 * 365.25 * 86400.0 : (i % 100 == 0 ? 1.0 : 0.0);  // NTP at 150 s
    sink.add(all[i], estimator.update(all[i]), estimator);
  }
  headingd::core::MemorySource source(all);
  sink.finish(estimator, source);
  const auto names = names_in(settings.dir);
  ASSERT_EQ(names.size(), 5u) << "the run's five files, the earlier run's gone";
  EXPECT_EQ(sink.files_deleted(), 1u);
  EXPECT_EQ(std::count_if(names.begin(), names.end(), [](const auto& n) { return n.starts_with("headingd-2000"); }), 3)
      << "three files started before the clock was set, kept";
  std::size_t total = 0;
  for (const auto& name : names) total += samples_in(settings.dir + "/" + name);
  EXPECT_EQ(total, all.size());
  fake_now_s = 1796000000.0;
}

namespace {

// The file-size limit of this process (RLIMIT_FSIZE) as a disk that fills: a write past it fails
// with EFBIG as one past a full disk fails with ENOSPC, in the same place (CsvOut's flush).
class FileSizeLimit {
 public:
  explicit FileSizeLimit(rlim_t bytes) {
    ::getrlimit(RLIMIT_FSIZE, &saved_);
    previous_handler_ = std::signal(SIGXFSZ, SIG_IGN);  // the error, not the signal that kills
    const rlimit limit{bytes, saved_.rlim_max};
    ::setrlimit(RLIMIT_FSIZE, &limit);
  }
  ~FileSizeLimit() { lift(); }
  FileSizeLimit(const FileSizeLimit&) = delete;
  FileSizeLimit& operator=(const FileSizeLimit&) = delete;
  void lift() {
    if (lifted_) return;
    ::setrlimit(RLIMIT_FSIZE, &saved_);
    std::signal(SIGXFSZ, previous_handler_);
    lifted_ = true;
  }

 private:
  rlimit saved_{};
  void (*previous_handler_)(int) = SIG_DFL;
  bool lifted_ = false;
};

// Noisy rates: what a sensor gives, and text zstd cannot squeeze into nothing.
std::vector<headingd::core::Sample> noisy_samples(double from_s, double seconds, double rate_hz) {
  std::mt19937 random(7);
  std::normal_distribution<double> noise(0.0, 0.05);
  std::vector<headingd::core::Sample> out;
  for (int i = 0; i < static_cast<int>(seconds * rate_hz); ++i) {
    headingd::core::Sample s;
    s.t_s = from_s + i / rate_hz;
    s.rate_dps = {noise(random), noise(random), 0.3 + noise(random)};
    s.temp_c = 25.0;
    out.push_back(s);
  }
  return out;
}

// A series that resumes after write errors (as beside DDS) in a fresh folder; through(t) feeds
// `all` up to sample time t as the pipeline would, the fake clock one second on per 100 samples.
struct ResumingSeries {
  ResumingSeries(double split_s, std::vector<headingd::core::Sample> samples, std::string comments = "")
      : settings{dir.path("rec"), split_s / 3600.0, 48.0},
        sink(settings, std::move(comments), fake_wall),
        all(std::move(samples)) {
    sink.resume_after_errors(drops);
  }
  void through(double until_s) {
    for (; next < all.size() && all[next].t_s < until_s; ++next) {
      if (next % 100 == 0) fake_now_s += 1.0;
      sink.add(all[next], estimator.update(all[next]), estimator);
    }
  }
  void finish() {
    through(1e18);
    headingd::core::MemorySource source(all);
    sink.finish(estimator, source);
  }
  std::vector<std::string> names() const { return names_in(settings.dir); }
  std::string path(const std::string& name) const { return settings.dir + "/" + name; }

  TempDir dir;
  RollingSettings settings;
  RollingRecordingSink sink;
  headingd::pipeline::OutputDrops drops;
  headingd::core::Estimator estimator{headingd::core::kDefaultEstimatorSettings};
  std::vector<headingd::core::Sample> all;
  std::size_t next = 0;
};

}  // namespace

// A disk that fills mid-file and has room again later: the file keeps what it holds, the
// samples in between are not recorded, a new file starts after the wait and the series goes on;
// the drop is counted once. A file that got nothing onto the disk is removed.
TEST(RollingRecording, AFileThatCannotBeWrittenIsFollowedByANewOne) {
  ResumingSeries series(180.0, noisy_samples(100.0, 700.0, 100.0), "# sensor: hand-made\n");  // a file per 3 min
  {
    FileSizeLimit full(rlim_t{64} * 1024);  // the first 1 MB of text CsvOut hands on fails past 64 kB
    series.through(400.0);
    EXPECT_EQ(series.drops.failing, 1u) << "not writing: /diagnostics warns";
    series.through(500.0);
  }
  series.finish();
  EXPECT_EQ(series.drops.failing, 0u) << "writing again: /diagnostics OK, the count stays";
  EXPECT_EQ(series.drops.count, 1u) << series.drops.last;
  EXPECT_NE(series.drops.last.find("cannot write"), std::string::npos) << series.drops.last;
  EXPECT_EQ(series.sink.files_lost(), 1u);
  const auto names = series.names();
  ASSERT_EQ(names.size(), 3u) << "the lost file (what it holds), the one that resumed, the next";
  EXPECT_LE(fs::file_size(series.path(names[0])), 64u * 1024u);
  EXPECT_GT(fs::file_size(series.path(names[0])), 0u);
  EXPECT_THROW(samples_in(series.path(names[0])), headingd::drivers::InputError) << "cut short";
  // The first file failed at its first 1 MB of text (~15,000 samples in); the next one is tried
  // 180 s (one split) of samples later and, with the file after it, holds every sample from there.
  const auto resumed = read_samples(series.path(names[1]));
  const auto last = read_samples(series.path(names[2]));
  ASSERT_FALSE(resumed.empty());
  ASSERT_FALSE(last.empty());
  EXPECT_EQ(resumed.size(), 18000u) << "a whole split";
  EXPECT_GT(resumed.front().t_s, 100.0 + 180.0) << "not before the wait after the loss";
  EXPECT_LT(resumed.front().t_s, 500.0) << "started while the disk was full; its first write came after";
  const auto from_resume =
      std::count_if(series.all.begin(), series.all.end(), [&](const auto& s) { return s.t_s >= resumed.front().t_s; });
  EXPECT_EQ(static_cast<std::size_t>(from_resume), resumed.size() + last.size());
  EXPECT_DOUBLE_EQ(last.back().t_s, series.all.back().t_s);
}

// No room at all: each file is lost at its first write, holds nothing and is removed; the run
// goes on trying, one split apart, every loss counted.
TEST(RollingRecording, FilesThatGotNothingOntoTheDiskAreRemoved) {
  ResumingSeries series(60.0, noisy_samples(0.0, 400.0, 100.0));
  {
    FileSizeLimit full(0);
    series.finish();
  }
  EXPECT_TRUE(series.names().empty());
  // Started at 0 s and lost at its split (60 s: CsvOut had not written before), tried again at
  // 120 s and lost at 180 s, and so on: 0, 120, 240, 360 (the last lost at finish).
  EXPECT_EQ(series.sink.files_started(), 4u);
  EXPECT_EQ(series.sink.files_lost(), 4u);
  EXPECT_EQ(series.drops.count, 4u);
  EXPECT_EQ(series.drops.failing, 1u);
}

// Files shorter than kWritingAgainS (a split of 5 s) and fed faster than real time: the series is
// writing again once a file since the loss closed without an error and 10 s of samples passed
// since it resumed, counted across the splits; not while the resumed file has put nothing on the
// disk.
TEST(RollingRecording, WritingAgainIsCountedAcrossSplitsOnceSamplesReachedTheDisk) {
  ResumingSeries series(5.0, noisy_samples(0.0, 60.0, 100.0));
  {
    FileSizeLimit full(0);
    series.through(5.5);  // the first file lost when the split at 5 s closed it; the next is tried at 10 s
    EXPECT_EQ(series.drops.failing, 1u);
  }
  series.through(14.0);  // resumed at 10 s: open, nothing of it on the disk yet
  EXPECT_EQ(series.drops.failing, 1u) << "a file that has written nothing is not writing again";
  series.through(19.9);  // the resumed file closed at 15 s; 10 s since the resume not yet passed
  EXPECT_EQ(series.drops.failing, 1u);
  series.through(20.1);
  EXPECT_EQ(series.drops.failing, 0u) << "writing again across splits shorter than 10 s";
  EXPECT_EQ(series.drops.count, 1u) << series.drops.last;
}

// The folder removed by hand under a running series (a clean-up): the file being written is lost
// with it, the next split makes the folder again and the series goes on.
TEST(RollingRecording, AFolderRemovedMidRunComesBackAtTheNextSplit) {
  ResumingSeries series(60.0, samples(200.0, 100.0));  // samples from 100 s to 300 s
  series.through(190.0);                               // the second file open
  fs::remove_all(series.settings.dir);
  series.finish();
  const auto names = series.names();
  ASSERT_EQ(names.size(), 2u) << "the files from 220 s on";
  std::size_t total = 0;
  for (const auto& name : names) total += samples_in(series.path(name));
  EXPECT_EQ(total, 8000u) << "220 s to 300 s";
}

// Thirteen files within one second of the wall clock (a replay at full speed, restarts in a
// loop): the names still sort in the order the files were started, as `replay --join` takes them.
TEST(RollingRecording, NamesSortInStartOrderPastTenInOneSecond) {
  TempDir dir;
  RollingSettings settings{dir.path("rec"), 1.0 / 3600.0, 48.0};
  RollingRecordingSink sink(settings, "", [] { return 1796000000.0; });
  headingd::core::Estimator estimator(headingd::core::kDefaultEstimatorSettings);
  for (const auto& s : samples(12.5, 100.0)) sink.add(s, estimator.update(s), estimator);
  headingd::core::MemorySource source({});
  sink.finish(estimator, source);
  const auto names = names_in(settings.dir);
  ASSERT_EQ(names.size(), 13u);
  EXPECT_EQ(names[12], "headingd-20261130T005320Z_012.csv.zst");
  double previous_t = -1.0;
  for (const auto& name : names) {
    const auto first_t = read_samples(settings.dir + "/" + name).front().t_s;
    EXPECT_GT(first_t, previous_t) << name;
    previous_t = first_t;
  }
}
