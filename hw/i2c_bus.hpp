#pragma once
// The I2C transport the L3GD20H driver needs: one combined write-then-read (repeated START,
// as the datasheet's read protocol requires, DS Tables 15/16) and a plain write.
// Implemented over Linux i2c-dev (linux_i2c_bus.hpp) and by the chip simulator.
#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>

namespace headingd::drivers {

class I2cError : public std::runtime_error {
 public:
  enum class Kind {
    NoAck,       // ENXIO, EREMOTEIO, ENODEV: the device did not acknowledge
    BusTrouble,  // ETIMEDOUT, EAGAIN, EIO, EBUSY: retry, then recover
    Other,       // anything else (EOPNOTSUPP, EINVAL...): not worth retrying
  };
  I2cError(Kind kind, int error_number, const std::string& what)
      : std::runtime_error(what), kind_(kind), errno_(error_number) {}
  Kind kind() const { return kind_; }
  int error_number() const { return errno_; }
  bool retryable() const { return kind_ != Kind::Other; }

 private:
  Kind kind_;
  int errno_;
};

class I2cBus {
 public:
  virtual ~I2cBus() = default;
  // Writes `tx`, then (repeated START) reads rx.size() bytes, in one transaction. Throws I2cError.
  virtual void write_read(std::uint8_t address, std::span<const std::uint8_t> tx, std::span<std::uint8_t> rx) = 0;
  virtual void write(std::uint8_t address, std::span<const std::uint8_t> tx) = 0;
  virtual std::string describe() const = 0;
};

}  // namespace headingd::drivers
