#pragma once
// I2cBus over Linux i2c-dev: /dev/i2c-N, one I2C_RDWR ioctl per transaction (write then
// read with a repeated START; docs/l3gd20h.md section 6). errno values are mapped to the
// I2cError kinds the driver retries on.
#include <string>

#include "hw/i2c_bus.hpp"

namespace headingd::drivers {

class LinuxI2cBus final : public I2cBus {
 public:
  // Opens the adapter; throws std::runtime_error naming the path and the likely fix.
  explicit LinuxI2cBus(std::string path);
  ~LinuxI2cBus() override;
  LinuxI2cBus(const LinuxI2cBus&) = delete;
  LinuxI2cBus& operator=(const LinuxI2cBus&) = delete;

  void write_read(std::uint8_t address, std::span<const std::uint8_t> tx, std::span<std::uint8_t> rx) override;
  void write(std::uint8_t address, std::span<const std::uint8_t> tx) override;
  std::string describe() const override { return path_; }

  // The message for an errno from open() on `path`, shared with the GPIO side.
  static std::string open_error(const std::string& what, const std::string& path, int error_number,
                                const std::string& group);

 private:
  [[noreturn]] void fail(const char* operation, std::uint8_t address, std::size_t bytes, int error_number) const;
  std::string path_;
  int fd_ = -1;
};

}  // namespace headingd::drivers
