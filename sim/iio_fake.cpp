#include "sim/iio_fake.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <stdexcept>

namespace headingd::drivers {
namespace {

namespace fs = std::filesystem;

void put(const fs::path& path, const std::string& value) {
  fs::create_directories(path.parent_path());
  std::ofstream out(path, std::ios::trunc);
  out << value << "\n";
  if (!out) throw std::runtime_error("fake IIO: cannot write " + path.string());
}

std::string scale_text(double scale) {
  char text[64];
  std::snprintf(text, sizeof text, "%.9f", scale);
  return text;
}

struct ChannelSpec {
  const char* name;
  unsigned index;
  const char* type;
};

struct LayoutSpec {
  const char* name;
  const char* scan_dir;    // scan_elements or buffer0
  const char* buffer_dir;  // buffer or buffer0
  std::vector<ChannelSpec> channels;
  double scale;  // rad/s per LSB
  Eigen::Vector3d offset;
  const char* mount;  // "" = no attribute
  const char* trigger;
  const char* frequency;
  const char* available;
};

const LayoutSpec& spec_of(FakeIioLayout layout) {
  // st_gyro (L3GD20H at 245 dps): 8.75 mdps/LSB = 152.7e-6 rad/s (DS Table 3).
  static const LayoutSpec st16{"l3gd20h",
                               "scan_elements",
                               "buffer",
                               {{"in_anglvel_x", 0, "le:s16/16>>0"},
                                {"in_anglvel_y", 1, "le:s16/16>>0"},
                                {"in_anglvel_z", 2, "le:s16/16>>0"},
                                {"in_timestamp", 3, "le:s64/64>>0"}},
                               8.75e-3 * std::numbers::pi / 180.0,
                               Eigen::Vector3d::Zero(),
                               "",
                               "l3gd20h-trigger",
                               "380",
                               "95 190 380 760"};
  // A 20-bit big-endian gyro in 32-bit words, channels in the order z, y, x, an accelerometer
  // channel between them and the timestamp, per-axis offsets; newer kernels' buffer0/ (beside
  // the legacy names).
  static const LayoutSpec be32{"fake32",
                               "buffer0",
                               "buffer0",
                               {{"in_anglvel_z", 0, "be:s20/32>>4"},
                                {"in_anglvel_y", 1, "be:s20/32>>4"},
                                {"in_anglvel_x", 2, "be:s20/32>>4"},
                                {"in_accel_x", 3, "le:s16/16>>0"},
                                {"in_timestamp", 4, "le:s64/64>>0"}},
                               1e-6,
                               Eigen::Vector3d(2.0, -3.0, 5.0),
                               "",
                               "fake32-dev0",
                               "400",
                               "[100 1 1000]"};
  // A BMI160-like 16-bit gyro mounted with x and y swapped and z down.
  static const LayoutSpec swapped{"bmi160",
                                  "scan_elements",
                                  "buffer",
                                  {{"in_anglvel_x", 0, "le:s16/16>>0"},
                                   {"in_anglvel_y", 1, "le:s16/16>>0"},
                                   {"in_anglvel_z", 2, "le:s16/16>>0"},
                                   {"in_timestamp", 3, "le:s64/64>>0"}},
                                  0.000266316,
                                  Eigen::Vector3d::Zero(),
                                  "0, 1, 0; 1, 0, 0; 0, 0, -1",
                                  "bmi160-dev0",
                                  "400",
                                  "25 50 100 200 400 800 1600 3200"};
  switch (layout) {
    case FakeIioLayout::St16:
      return st16;
    case FakeIioLayout::Be32Shift:
      return be32;
    case FakeIioLayout::SwappedMount:
      return swapped;
  }
  return st16;
}

// Kernels from 5.11 show the first buffer twice: as buffer0/ and, for the programs written before
// it, as the legacy buffer/ and scan_elements/ (the same attributes under both names,
// Documentation/ABI/testing/sysfs-bus-iio, "buffer/length ... Since Kernel 5.11"). Symbolic links
// give the fake the same: a write under either name is seen under the other.
void link_legacy_buffer_dirs(const fs::path& dir, const LayoutSpec& spec) {
  const auto link = [&](const char* legacy, const std::string& file) {
    fs::create_directories(dir / legacy);
    fs::remove(dir / legacy / file);  // a tree created again over an old one
    fs::create_symlink(fs::path("../buffer0") / file, dir / legacy / file);
  };
  for (const auto& c : spec.channels)
    for (const char* suffix : {"_en", "_index", "_type"}) link("scan_elements", std::string(c.name) + suffix);
  for (const char* control : {"enable", "length", "watermark"}) link("buffer", control);
}

}  // namespace

FakeIioTree::FakeIioTree(FakeIioOptions options) : options_(std::move(options)) {
  const auto& spec = spec_of(options_.layout);
  std::vector<iio::ScanChannel> channels;
  for (const auto& c : spec.channels) {
    iio::ScanChannel channel;
    channel.name = c.name;
    channel.index = c.index;
    std::string why;
    channel.type = *iio::parse_channel_type(c.type, why);
    if (channel.name != "in_accel_x") channels.push_back(channel);  // the accelerometer stays disabled
  }
  layout_ = iio::ScanLayout(std::move(channels));
  for (std::size_t axis = 0; axis < 3; ++axis)
    axes_[axis] =
        static_cast<std::size_t>(layout_.find(std::string("in_anglvel_") + "xyz"[axis]) - layout_.channels().data());
  timestamp_ = static_cast<std::size_t>(layout_.find("in_timestamp") - layout_.channels().data());
  // The reader sees the scale as the text the tree holds; the expected values use the same.
  scale_ = Eigen::Vector3d::Constant(std::strtod(scale_text(spec.scale).c_str(), nullptr));
  offset_ = spec.offset;
  mount_ = Eigen::Matrix3d::Identity();
  if (spec.mount[0] != '\0') mount_ << 0, 1, 0, 1, 0, 0, 0, 0, -1;
}

std::string FakeIioTree::device_dir() const {
  return options_.root + "/sys/bus/iio/devices/iio:device" + std::to_string(options_.number);
}
std::string FakeIioTree::dev_node() const {
  return options_.root + "/dev/iio:device" + std::to_string(options_.number);
}
std::string FakeIioTree::name() const { return spec_of(options_.layout).name; }

void FakeIioTree::create() {
  const auto& spec = spec_of(options_.layout);
  const fs::path dir = device_dir();
  put(dir / "name", spec.name);
  for (const auto& c : spec.channels) {
    put(dir / spec.scan_dir / (std::string(c.name) + "_en"), "0");
    put(dir / spec.scan_dir / (std::string(c.name) + "_index"), std::to_string(c.index));
    put(dir / spec.scan_dir / (std::string(c.name) + "_type"), c.type);
  }
  put(dir / "in_anglvel_scale", scale_text(spec.scale));
  if (spec.offset != Eigen::Vector3d::Zero())
    for (int axis = 0; axis < 3; ++axis)
      put(dir / (std::string("in_anglvel_") + "xyz"[axis] + "_offset"),
          std::to_string(static_cast<int>(spec.offset[axis])));
  if (spec.mount[0] != '\0') put(dir / "in_anglvel_mount_matrix", spec.mount);
  put(dir / "sampling_frequency", spec.frequency);
  put(dir / "sampling_frequency_available", spec.available);
  put(dir / "current_timestamp_clock", "realtime");
  put(dir / spec.buffer_dir / "enable", "0");
  put(dir / spec.buffer_dir / "length", "0");
  put(dir / spec.buffer_dir / "watermark", "1");
  put(dir / "trigger" / "current_trigger", "");
  if (std::string(spec.scan_dir) == "buffer0") link_legacy_buffer_dirs(dir, spec);
  // of_node/compatible: NUL-terminated strings, no newline.
  const std::string compatible = std::string("st,") + spec.name + "-gyro" + '\0' + "headingd,fake-gyro" + '\0';
  fs::create_directories(dir / "of_node");
  std::ofstream(dir / "of_node" / "compatible", std::ios::binary) << compatible;
  const fs::path trigger =
      fs::path(options_.root) / "sys/bus/iio/devices" / ("trigger" + std::to_string(options_.number));
  put(trigger / "name", spec.trigger);
  if (options_.layout == FakeIioLayout::Be32Shift) put(dir / "in_temp_input", "31500");
  if (options_.layout == FakeIioLayout::SwappedMount) {
    put(dir / "in_temp_raw", "512");
    put(dir / "in_temp_scale", "1.953125");  // m degC per LSB
    put(dir / "in_temp_offset", "11776");    // 23 degC at raw 0
  }
  fs::create_directories(fs::path(dev_node()).parent_path());
  if (::mkfifo(dev_node().c_str(), 0660) != 0 && errno != EEXIST)
    throw std::runtime_error("fake IIO: mkfifo " + dev_node() + ": " + std::strerror(errno));
}

void FakeIioTree::remove() {
  fs::remove_all(device_dir());
  fs::remove_all(fs::path(options_.root) / "sys/bus/iio/devices" / ("trigger" + std::to_string(options_.number)));
  fs::remove(dev_node());
}

std::vector<std::int64_t> FakeIioTree::raw_of(const core::Vec3& rate_dps) const {
  const Eigen::Vector3d device = mount_.transpose() * (rate_dps * std::numbers::pi / 180.0);
  std::vector<std::int64_t> raw(3);
  for (std::size_t axis = 0; axis < 3; ++axis) {
    const auto i = static_cast<Eigen::Index>(axis);
    const auto& type = layout_.channels()[axes_[axis]].type;
    const double limit = std::ldexp(1.0, static_cast<int>(type.bits) - 1);
    const double value = std::clamp(std::round(device[i] / scale_[i] - offset_[i]), -limit, limit - 1);
    raw[axis] = static_cast<std::int64_t>(value);
  }
  return raw;
}

void FakeIioTree::encode(const core::Vec3& rate_dps, std::int64_t t_ns, std::span<std::uint8_t> scan) const {
  std::fill(scan.begin(), scan.end(), std::uint8_t{0xA5});  // padding is garbage in a real buffer too
  const auto raw = raw_of(rate_dps);
  for (std::size_t axis = 0; axis < 3; ++axis) iio::encode(layout_.channels()[axes_[axis]], raw[axis], scan);
  iio::encode(layout_.channels()[timestamp_], t_ns, scan);
}

core::Vec3 FakeIioTree::quantised(const core::Vec3& rate_dps) const {
  const auto raw = raw_of(rate_dps);
  Eigen::Vector3d device;
  for (std::size_t axis = 0; axis < 3; ++axis) {
    const auto i = static_cast<Eigen::Index>(axis);
    device[i] = (static_cast<double>(raw[axis]) + offset_[i]) * scale_[i];
  }
  return mount_ * device * (180.0 / std::numbers::pi);
}

void FakeIioTree::set(const std::string& attribute, const std::string& value) const {
  const fs::path path = fs::path(device_dir()) / attribute;
  const fs::path temporary = path.string() + ".new";
  put(temporary, value);
  fs::rename(temporary, path);  // a reader never sees half a value
}

std::string FakeIioTree::get(const std::string& attribute) const {
  std::ifstream in(fs::path(device_dir()) / attribute);
  std::string value;
  std::getline(in, value);
  return value;
}

FakeIioWriter::FakeIioWriter(const FakeIioTree& tree) {
  fd_ = ::open(tree.dev_node().c_str(), O_WRONLY | O_CLOEXEC);  // blocks until the reader opens it
  if (fd_ < 0) throw std::runtime_error("fake IIO: cannot open " + tree.dev_node() + ": " + std::strerror(errno));
}

FakeIioWriter::~FakeIioWriter() { close(); }

bool FakeIioWriter::write(std::span<const std::uint8_t> bytes) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd_, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    done += static_cast<std::size_t>(n);
  }
  return true;
}

void FakeIioWriter::close() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

}  // namespace headingd::drivers
