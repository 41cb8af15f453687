// The IIO gyro source against a fake IIO tree (a directory standing in for /sys and /dev, a
// FIFO for /dev/iio:deviceN) fed by the gyro simulator in three real scan layouts.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cmath>
#include <csignal>
#include <filesystem>
#include <thread>

#include "hw/iio_gyro.hpp"
#include "sim/gyro_simulator.hpp"
#include "sim/iio_fake.hpp"
#include "temp_dir.hpp"

using namespace headingd;
using drivers::FakeIioLayout;

namespace {

constexpr double kTrueRateHz = 378.8;  // the chip's real rate, not the nominal 380
constexpr std::int64_t kStartNs = 5'000'000'000'000;

struct Fed {
  std::vector<core::Vec3> truth;     // the simulator's rates
  std::vector<core::Vec3> expected;  // what a perfect decoder gives (quantised)
  std::vector<std::int64_t> stamps;
};

// Writes `n` scans from the simulator's agv scenario into the fake's FIFO, skipping `skip`.
void feed(const drivers::FakeIioTree& tree, std::size_t n, Fed& fed, std::size_t first_index = 0,
          const std::vector<std::size_t>& skip = {}) {
  auto scenario = *drivers::build_scenario("agv", 7, 0.0);
  drivers::GyroSimulator sim(scenario, 7);
  drivers::FakeIioWriter writer(tree);
  const std::size_t bytes = tree.layout().scan_bytes();
  std::vector<std::uint8_t> burst;
  for (std::size_t i = 0; i < first_index + n; ++i) {
    core::Sample s;
    drivers::TruthPoint t;
    sim.step(s, t);
    if (i < first_index) continue;
    if (std::find(skip.begin(), skip.end(), i) != skip.end()) continue;
    // Time stamps with a little jitter, as the kernel's interrupt time stamps have.
    const auto t_ns = kStartNs + static_cast<std::int64_t>(static_cast<double>(i) * 1e9 / kTrueRateHz) +
                      static_cast<std::int64_t>((i * 7919) % 13) * 1000;
    const std::size_t at = burst.size();
    burst.resize(at + bytes);
    tree.encode(s.rate_dps, t_ns, std::span(burst).subspan(at, bytes));
    fed.truth.push_back(s.rate_dps);
    fed.expected.push_back(tree.quantised(s.rate_dps));
    fed.stamps.push_back(t_ns);
    if (burst.size() >= 16 * bytes) {  // a watermark's worth per write, as the kernel hands them over
      ASSERT_TRUE(writer.write(burst));
      burst.clear();
    }
  }
  if (!burst.empty()) {
    ASSERT_TRUE(writer.write(burst));
  }
}

std::vector<core::Sample> read_n(drivers::IioGyro& gyro, std::size_t n) {
  std::vector<core::Sample> all, batch(64);
  while (all.size() < n) {
    const auto got = gyro.read(batch);
    if (got == 0) break;
    all.insert(all.end(), batch.begin(), batch.begin() + static_cast<long>(got));
  }
  return all;
}

drivers::IioSettings settings_for(const test::TempDir& dir, double frequency_hz = 400.0) {
  drivers::IioSettings s;
  s.root = dir.path("root");
  s.sampling_frequency_hz = frequency_hz;
  return s;
}

class IioLayouts : public ::testing::TestWithParam<FakeIioLayout> {};

}  // namespace

TEST(IioScan, ParsesTheKernelsTypeDescriptors) {
  std::string why;
  auto t = drivers::iio::parse_channel_type("le:s16/16>>0\n", why);
  ASSERT_TRUE(t);
  EXPECT_FALSE(t->big_endian);
  EXPECT_TRUE(t->is_signed);
  EXPECT_EQ(t->bits, 16u);
  t = drivers::iio::parse_channel_type("be:u12/16X3>>4", why);
  ASSERT_TRUE(t);
  EXPECT_TRUE(t->big_endian);
  EXPECT_FALSE(t->is_signed);
  EXPECT_EQ(t->repeat, 3u);
  EXPECT_EQ(t->shift, 4u);
  EXPECT_EQ(t->storage_bytes(), 6u);
  for (const char* bad : {"", "xe:s16/16>>0", "le:q16/16>>0", "le:s16/12>>0", "le:s16/16>>1", "le:s16/16",
                          "le:s0/16>>0", "le:s16/24>>0", "le:s16/16>>0 junk"})
    EXPECT_FALSE(drivers::iio::parse_channel_type(bad, why)) << bad;
}

TEST(IioScan, PlacesChannelsAsTheKernelDoes) {
  std::string why;
  const auto ch = [&](const char* name, unsigned index, const char* type) {
    return drivers::iio::ScanChannel{name, index, *drivers::iio::parse_channel_type(type, why), 0};
  };
  // st_gyro: three s16 and the timestamp aligned to 8: 16 bytes.
  drivers::iio::ScanLayout st({ch("in_timestamp", 3, "le:s64/64>>0"), ch("in_anglvel_z", 2, "le:s16/16>>0"),
                               ch("in_anglvel_x", 0, "le:s16/16>>0"), ch("in_anglvel_y", 1, "le:s16/16>>0")});
  EXPECT_EQ(st.scan_bytes(), 16u);
  EXPECT_EQ(st.find("in_anglvel_y")->offset, 2u);
  EXPECT_EQ(st.find("in_timestamp")->offset, 8u);
  // One 16-bit channel then a 32-bit one: the 32-bit one starts at 4, the scan pads to 16 with the timestamp.
  drivers::iio::ScanLayout mixed(
      {ch("a", 0, "le:s16/16>>0"), ch("b", 1, "be:s20/32>>4"), ch("in_timestamp", 2, "le:s64/64>>0")});
  EXPECT_EQ(mixed.find("b")->offset, 4u);
  EXPECT_EQ(mixed.find("in_timestamp")->offset, 8u);
  EXPECT_EQ(mixed.scan_bytes(), 16u);
  EXPECT_THROW(drivers::iio::ScanLayout({ch("a", 0, "le:s16/16>>0"), ch("b", 0, "le:s16/16>>0")}),
               std::invalid_argument);
  // Sign, shift and byte order round-trip at the extremes.
  std::vector<std::uint8_t> scan(16);
  for (std::int64_t v : {-524288L, -1L, 0L, 1L, 524287L}) {
    drivers::iio::encode(*mixed.find("b"), v, scan);
    EXPECT_EQ(drivers::iio::decode(*mixed.find("b"), scan), v);
  }
  scan.assign(16, 0);
  scan[5] = 0x80;  // big-endian word 0x00800000: bit 23 = the sign of 20 bits above a shift of 4
  EXPECT_EQ(drivers::iio::decode(*mixed.find("b"), scan), -524288);
}

TEST(IioScan, ParsesMountMatrices) {
  const auto m = drivers::parse_mount_matrix("0, 1, 0; 1, 0, 0; 0, 0, -1");
  ASSERT_TRUE(m);
  EXPECT_EQ((*m)(0, 1), 1.0);
  EXPECT_EQ((*m)(2, 2), -1.0);
  EXPECT_FALSE(drivers::parse_mount_matrix("1, 0, 0; 0, 1, 0"));
  EXPECT_FALSE(drivers::parse_mount_matrix("1, 0, 0; 0, 1, 0; 0, 0, 1; 4"));
  EXPECT_FALSE(drivers::parse_mount_matrix("1, 0, 0; 0, nan, 0; 0, 0, 1"));
}

TEST_P(IioLayouts, DecodeToTheSimulatorsRatesWithTimeAndRate) {
  test::TempDir dir;
  drivers::FakeIioTree tree({dir.path("root"), GetParam(), 0});
  tree.create();
  drivers::IioGyro gyro(settings_for(dir));
  // What the source set up in sysfs.
  const bool buffer0 = GetParam() == FakeIioLayout::Be32Shift;
  const std::string buffer = buffer0 ? "buffer0/" : "buffer/";
  const std::string scan = buffer0 ? "buffer0/" : "scan_elements/";
  EXPECT_EQ(tree.get(buffer + "enable"), "1");
  EXPECT_EQ(tree.get(scan + "in_anglvel_x_en"), "1");
  EXPECT_EQ(tree.get(scan + "in_timestamp_en"), "1");
  if (buffer0) {
    EXPECT_EQ(tree.get(scan + "in_accel_x_en"), "0");
  }
  EXPECT_EQ(tree.get("current_timestamp_clock"), "monotonic");
  EXPECT_EQ(tree.get(buffer + "length"), "256");
  EXPECT_EQ(tree.get(buffer + "watermark"), "7");
  EXPECT_EQ(tree.get("sampling_frequency"), GetParam() == FakeIioLayout::St16 ? "380" : "400");  // nearest offered
  EXPECT_EQ(tree.get("trigger/current_trigger"),
            tree.name() + (GetParam() == FakeIioLayout::St16 ? "-trigger" : "-dev0"));

  constexpr std::size_t kScans = 6000;
  Fed fed;
  std::thread writer([&] { feed(tree, kScans, fed); });
  const auto got = read_n(gyro, kScans);
  writer.join();
  ASSERT_EQ(got.size(), kScans);
  double worst_vs_truth = 0.0, lsb_dps = 0.0;
  for (std::size_t i = 0; i < kScans; ++i) {
    ASSERT_EQ(got[i].rate_dps, fed.expected[i]) << "scan " << i;  // exactly, after scale, offset and mount
    ASSERT_EQ(got[i].t_s, static_cast<double>(fed.stamps[i]) / 1e9) << "scan " << i;
    worst_vs_truth = std::max(worst_vs_truth, (got[i].rate_dps - fed.truth[i]).cwiseAbs().maxCoeff());
  }
  lsb_dps = std::strtod(tree.get("in_anglvel_scale").c_str(), nullptr) * 180.0 / M_PI;
  EXPECT_LE(worst_vs_truth, 0.5 * lsb_dps + 1e-12) << "more than half an LSB from the simulator";
  EXPECT_NEAR(gyro.rate_hz(), kTrueRateHz, kTrueRateHz * 1e-3);
  EXPECT_EQ(gyro.counters().lost_samples, 0u);
  if (GetParam() == FakeIioLayout::SwappedMount) {
    // The mount matrix swaps x and y and turns z over: a turn about the chip's -z is a vehicle yaw.
    EXPECT_NEAR(got[100].temp_c, (512 + 11776) * 1.953125 / 1000.0, 1e-9);
  }
  if (GetParam() == FakeIioLayout::Be32Shift) {
    EXPECT_NEAR(got[100].temp_c, 31.5, 1e-9);
  }
  if (GetParam() == FakeIioLayout::St16) {
    EXPECT_TRUE(std::isnan(got[100].temp_c));
  }
  gyro.close();
  EXPECT_EQ(tree.get(buffer + "enable"), "0");
}

INSTANTIATE_TEST_SUITE_P(Fake, IioLayouts,
                         ::testing::Values(FakeIioLayout::St16, FakeIioLayout::Be32Shift, FakeIioLayout::SwappedMount),
                         [](const auto& layout) {
                           switch (layout.param) {
                             case FakeIioLayout::St16:
                               return std::string("St16LittleEndian");
                             case FakeIioLayout::Be32Shift:
                               return std::string("Be32ShiftedBuffer0");
                             case FakeIioLayout::SwappedMount:
                               return std::string("SwappedMountMatrix");
                           }
                           return std::string("unknown");
                         });

TEST(IioGyro, MountMatrixMakesTheVehiclesVertical) {
  test::TempDir dir;
  drivers::FakeIioTree tree({dir.path("root"), FakeIioLayout::SwappedMount, 0});
  tree.create();
  drivers::IioGyro gyro(settings_for(dir));
  // A raw scan by hand: chip x = +1000 LSB, chip z = +200 LSB.
  std::vector<std::uint8_t> scan(tree.layout().scan_bytes());
  drivers::iio::encode(*tree.layout().find("in_anglvel_x"), 1000, scan);
  drivers::iio::encode(*tree.layout().find("in_anglvel_y"), 0, scan);
  drivers::iio::encode(*tree.layout().find("in_anglvel_z"), 200, scan);
  drivers::iio::encode(*tree.layout().find("in_timestamp"), kStartNs, scan);
  std::thread writer([&] {
    drivers::FakeIioWriter w(tree);
    w.write(scan);
  });
  std::vector<core::Sample> out(4);
  ASSERT_EQ(gyro.read(out), 1u);
  writer.join();
  const double lsb = std::strtod(tree.get("in_anglvel_scale").c_str(), nullptr) * 180.0 / M_PI;
  EXPECT_EQ(out[0].rate_dps.x(), 0.0);
  EXPECT_DOUBLE_EQ(out[0].rate_dps.y(), 1000 * lsb);  // vehicle y = chip x
  EXPECT_DOUBLE_EQ(out[0].rate_dps.z(), -200 * lsb);  // vehicle z = -chip z
}

TEST(IioGyro, CountsDroppedScans) {
  test::TempDir dir;
  drivers::FakeIioTree tree({dir.path("root"), FakeIioLayout::St16, 0});
  tree.create();
  drivers::IioGyro gyro(settings_for(dir));
  Fed fed;
  std::thread writer([&] { feed(tree, 3000, fed, 0, {1000, 2000, 2001, 2002}); });
  const auto got = read_n(gyro, 2996);
  writer.join();
  EXPECT_EQ(got.size(), 2996u);
  EXPECT_EQ(gyro.counters().lost_samples, 4u);
  EXPECT_EQ(gyro.health().lost_samples, 4u);
}

TEST(IioGyro, RecoversWhenTheDeviceGoesAndComesBack) {
  test::TempDir dir;
  drivers::FakeIioTree tree({dir.path("root"), FakeIioLayout::St16, 0});
  tree.create();
  drivers::IioGyro gyro(settings_for(dir));
  std::vector<std::string> log;
  gyro.set_logger([&](int, const std::string&, const std::string& text) { log.push_back(text); });
  Fed first, second;
  std::thread writer([&] {
    feed(tree, 2000, first);
    // Unbound: the device and its node disappear, then the driver probes it again.
    tree.remove();
    std::this_thread::sleep_for(std::chrono::milliseconds(400));
    tree.create();
    feed(tree, 2000, second, 3000);
  });
  const auto got = read_n(gyro, 4000);
  writer.join();
  ASSERT_EQ(got.size(), 4000u);
  EXPECT_EQ(got[2000].rate_dps, second.expected[0]);
  EXPECT_EQ(gyro.counters().recoveries, 1u);
  EXPECT_EQ(gyro.health().recoveries, 1u);
  EXPECT_EQ(gyro.counters().lost_samples, 0u);  // the gap of a recovery is not counted as dropped scans
  ASSERT_GE(log.size(), 2u);
  EXPECT_NE(log.front().find("its buffer was closed; waiting for it to come back"), std::string::npos) << log.front();
  EXPECT_NE(log.back().find("is back and set up again"), std::string::npos) << log.back();
  EXPECT_EQ(tree.get("buffer/enable"), "1");
}

TEST(IioGyro, GivesUpOnADeviceThatStaysGone) {
  test::TempDir dir;
  drivers::FakeIioTree tree({dir.path("root"), FakeIioLayout::St16, 0});
  tree.create();
  auto settings = settings_for(dir);
  settings.give_up_s = 0.5;
  drivers::IioGyro gyro(settings);
  gyro.set_logger([](int, const std::string&, const std::string&) {});
  std::thread writer([&] {
    drivers::FakeIioWriter w(tree);
    tree.remove();
  });
  writer.join();
  std::vector<core::Sample> out(4);
  try {
    gyro.read(out);
    FAIL() << "read did not give up";
  } catch (const drivers::IioError& error) {
    EXPECT_NE(std::string(error.what()).find("has been gone for 0 s: no IIO device"), std::string::npos)
        << error.what();
  }
}

TEST(IioGyro, StopsOnTheStopFlag) {
  test::TempDir dir;
  drivers::FakeIioTree tree({dir.path("root"), FakeIioLayout::St16, 0});
  tree.create();
  drivers::IioGyro gyro(settings_for(dir));
  std::atomic<bool> stop{false};
  gyro.set_stop_flag(&stop);
  std::thread stopper([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(150));
    stop = true;
  });
  const auto start = std::chrono::steady_clock::now();
  std::vector<core::Sample> out(4);
  EXPECT_EQ(gyro.read(out), 0u);
  stopper.join();
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::milliseconds(400));
}

namespace {

std::string error_of(const drivers::IioSettings& settings) {
  try {
    drivers::IioGyro gyro(settings);
  } catch (const drivers::IioError& error) {
    return error.what();
  }
  return "no error";
}

}  // namespace

TEST(IioGyro, ErrorsSayWhatToDo) {
  test::TempDir dir;
  drivers::FakeIioTree tree({dir.path("root"), FakeIioLayout::St16, 0});
  tree.create();
  auto s = settings_for(dir);

  s.device = "bmi088";
  EXPECT_NE(error_of(s).find("no IIO device 'bmi088' under " + s.root +
                             "/sys/bus/iio/devices (found: iio:device0 (l3gd20h)); is the kernel driver loaded"),
            std::string::npos)
      << error_of(s);
  s.device = "st,l3gd20h-gyro";  // by the device tree's compatible
  EXPECT_EQ(error_of(s), "no error");
  s.device = "iio:device0";
  EXPECT_EQ(error_of(s), "no error");

  // An hrtimer trigger the operator made: chosen by name and set to tick at the device's rate.
  std::filesystem::create_directories(s.root + "/sys/bus/iio/devices/trigger5");
  std::ofstream(s.root + "/sys/bus/iio/devices/trigger5/name") << "headingd\n";
  std::ofstream(s.root + "/sys/bus/iio/devices/trigger5/sampling_frequency") << "100\n";
  s.trigger = "headingd";
  EXPECT_EQ(error_of(s), "no error");
  EXPECT_EQ(drivers::read_attribute(s.root + "/sys/bus/iio/devices/trigger5/sampling_frequency"), "380");
  EXPECT_EQ(tree.get("trigger/current_trigger"), "headingd");
  std::filesystem::remove_all(s.root + "/sys/bus/iio/devices/trigger5");

  s.trigger = "hrtimer7";
  tree.set("trigger/current_trigger", "");
  EXPECT_NE(error_of(s).find("no IIO trigger named 'hrtimer7' (have: l3gd20h-trigger); an hrtimer trigger is made "
                             "with: mkdir /sys/kernel/config/iio/triggers/hrtimer/hrtimer7"),
            std::string::npos)
      << error_of(s);
  s.trigger.clear();

  tree.set("buffer/enable", "1");
  EXPECT_NE(error_of(s).find("iio:device0 (l3gd20h): the buffer is already enabled by another consumer"),
            std::string::npos)
      << error_of(s);
  tree.set("buffer/enable", "0");

  std::filesystem::remove(tree.device_dir() + "/scan_elements/in_anglvel_z_en");
  EXPECT_NE(error_of(s).find("iio:device0 (l3gd20h) has no buffered channel in_anglvel_z"), std::string::npos)
      << error_of(s);
  tree.create();

  tree.set("scan_elements/in_anglvel_y_type", "le:s16/16>>4");
  EXPECT_NE(error_of(s).find("in_anglvel_y_type has bits, shift or repeat that do not fit its storage"),
            std::string::npos)
      << error_of(s);
  tree.create();

  std::filesystem::remove(tree.dev_node());
  EXPECT_NE(error_of(s).find("no device node " + tree.dev_node()), std::string::npos) << error_of(s);
  tree.create();

  // No trigger of its own and none named: the hrtimer recipe.
  std::filesystem::remove_all(s.root + "/sys/bus/iio/devices/trigger0");
  EXPECT_NE(error_of(s).find("has no trigger set and none of its own (triggers: none); make an hrtimer trigger"),
            std::string::npos)
      << error_of(s);
  tree.create();

  // Two gyros and no name: which one?
  drivers::FakeIioTree second({dir.path("root"), FakeIioLayout::SwappedMount, 1});
  second.create();
  s.device.clear();
  EXPECT_NE(error_of(s).find("more than one IIO device matches a gyro"), std::string::npos) << error_of(s);
  s.device = "bmi160";
  EXPECT_EQ(error_of(s), "no error");
}
