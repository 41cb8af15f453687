#pragma once
// A fake Linux IIO gyro for tests and benchmarks: a directory tree with the sysfs attributes a
// kernel driver exposes (name, scan elements, scale, mount matrix, buffer, trigger, sampling
// frequency, temperature) and a FIFO standing in for /dev/iio:deviceN, fed with scans encoded
// exactly as the kernel lays them out. Three layouts from real drivers: st_gyro's 16-bit
// little-endian scans with a 64-bit timestamp; a 32-bit big-endian one with a shift, channels
// out of order and per-axis offsets in buffer0/ (newer kernels); and a mount matrix that swaps
// x and y and turns z over.
#include <Eigen/Core>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/sample.hpp"
#include "hw/iio_scan.hpp"

namespace headingd::drivers {

enum class FakeIioLayout { St16, Be32Shift, SwappedMount };

struct FakeIioOptions {
  std::string root;  // the tree goes to <root>/sys/bus/iio/devices/iio:deviceN and <root>/dev
  FakeIioLayout layout = FakeIioLayout::St16;
  int number = 0;  // N in iio:deviceN
};

class FakeIioTree {
 public:
  explicit FakeIioTree(FakeIioOptions options);
  // Builds the tree (as a driver probing); remove() takes it away (as an unbind).
  void create();
  void remove();
  std::string device_dir() const;
  std::string dev_node() const;
  std::string name() const;
  const iio::ScanLayout& layout() const { return layout_; }
  // One scan for a vehicle-frame rate at a monotonic time; the rate is quantised to the LSB.
  void encode(const core::Vec3& rate_dps, std::int64_t t_ns, std::span<std::uint8_t> scan) const;
  // What a perfect reader decodes from encode(rate_dps): the quantised rate, vehicle frame.
  core::Vec3 quantised(const core::Vec3& rate_dps) const;
  // Writes a sysfs attribute of the device (a test changing the temperature, say).
  void set(const std::string& attribute, const std::string& value) const;
  std::string get(const std::string& attribute) const;

 private:
  FakeIioOptions options_;
  iio::ScanLayout layout_{{}};
  Eigen::Vector3d scale_, offset_;
  Eigen::Matrix3d mount_;
  std::array<std::size_t, 3> axes_{};
  std::size_t timestamp_ = 0;
  std::vector<std::int64_t> raw_of(const core::Vec3& rate_dps) const;
};

// Writes scans into the fake's FIFO: opens it (blocking until a reader has it open) and writes
// `scans` in bursts of `burst`, as a driver hands over a watermark's worth at a time.
class FakeIioWriter {
 public:
  explicit FakeIioWriter(const FakeIioTree& tree);
  ~FakeIioWriter();
  FakeIioWriter(const FakeIioWriter&) = delete;
  FakeIioWriter& operator=(const FakeIioWriter&) = delete;
  // False when the reader went away.
  bool write(std::span<const std::uint8_t> bytes);
  void close();

 private:
  int fd_ = -1;
};

}  // namespace headingd::drivers
