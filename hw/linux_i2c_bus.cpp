#include "hw/linux_i2c_bus.hpp"

#include <fcntl.h>
#include <linux/i2c-dev.h>
#include <linux/i2c.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>

namespace headingd::drivers {
namespace {

I2cError::Kind kind_of(int error_number) {
  switch (error_number) {
    case ENXIO:
    case EREMOTEIO:
    case ENODEV:
      return I2cError::Kind::NoAck;
    case ETIMEDOUT:
    case EAGAIN:
    case EIO:
    case EBUSY:
      return I2cError::Kind::BusTrouble;
    default:
      return I2cError::Kind::Other;
  }
}

const char* hint_of(int error_number) {
  switch (error_number) {
    case ENXIO:
    case EREMOTEIO:
      return " (the device did not acknowledge: wiring, address, power?)";
    case ETIMEDOUT:
      return " (the adapter timed out: bus stuck or clock stretched?)";
    case EOPNOTSUPP:
      return " (the adapter cannot do combined I2C transfers)";
    default:
      return "";
  }
}

}  // namespace

std::string LinuxI2cBus::open_error(const std::string& what, const std::string& path, int error_number,
                                    const std::string& group) {
  std::string message = "cannot open " + what + " " + path + ": " + std::strerror(error_number);
  if (error_number == ENOENT) {
    message += what == "I2C adapter" ? " (no such adapter: is the i2c-dev module loaded and the bus number right? "
                                       "see i2cdetect -l)"
                                     : " (no such GPIO chip: see gpiodetect)";
  } else if (error_number == EACCES || error_number == EPERM) {
    message += " (add the service user to group '" + group + "'; the shipped udev rule gives it mode 0660)";
  }
  return message;
}

LinuxI2cBus::LinuxI2cBus(std::string path) : path_(std::move(path)) {
  fd_ = ::open(path_.c_str(), O_RDWR | O_CLOEXEC);
  if (fd_ < 0) throw std::runtime_error(open_error("I2C adapter", path_, errno, "i2c"));
  unsigned long functions = 0;
  if (::ioctl(fd_, I2C_FUNCS, &functions) < 0) {
    const int error_number = errno;
    ::close(fd_);
    throw std::runtime_error(path_ + " is not an I2C adapter (I2C_FUNCS: " + std::strerror(error_number) + ")");
  }
  if ((functions & I2C_FUNC_I2C) == 0) {
    ::close(fd_);
    throw std::runtime_error(path_ +
                             ": the adapter cannot do plain I2C transfers (I2C_FUNC_I2C), which the "
                             "L3GD20H's burst reads need");
  }
}

LinuxI2cBus::~LinuxI2cBus() {
  if (fd_ >= 0) ::close(fd_);
}

void LinuxI2cBus::fail(const char* operation, std::uint8_t address, std::size_t bytes, int error_number) const {
  char text[256];
  std::snprintf(text, sizeof text, "%s address 0x%02x: %s of %zu bytes: %s%s", path_.c_str(), address, operation, bytes,
                std::strerror(error_number), hint_of(error_number));
  throw I2cError(kind_of(error_number), error_number, text);
}

void LinuxI2cBus::write_read(std::uint8_t address, std::span<const std::uint8_t> tx, std::span<std::uint8_t> rx) {
  i2c_msg messages[2] = {
      {address, 0, static_cast<__u16>(tx.size()), const_cast<__u8*>(tx.data())},
      {address, I2C_M_RD, static_cast<__u16>(rx.size()), rx.data()},
  };
  i2c_rdwr_ioctl_data data{messages, 2};
  if (::ioctl(fd_, I2C_RDWR, &data) < 0) fail("write-read", address, tx.size() + rx.size(), errno);
}

void LinuxI2cBus::write(std::uint8_t address, std::span<const std::uint8_t> tx) {
  i2c_msg message{address, 0, static_cast<__u16>(tx.size()), const_cast<__u8*>(tx.data())};
  i2c_rdwr_ioctl_data data{&message, 1};
  if (::ioctl(fd_, I2C_RDWR, &data) < 0) fail("write", address, tx.size(), errno);
}

}  // namespace headingd::drivers
