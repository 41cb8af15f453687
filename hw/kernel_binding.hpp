#pragma once
// Whether a kernel driver already owns the chip. Mainline Linux binds its st_gyro IIO driver to
// an L3GD20H described in the device tree (compatible "st,l3gd20h-gyro"); i2c-dev's I2C_RDWR
// does not check that the address is busy, so headingd and the kernel would both program the
// chip's registers. sysfs says it: /sys/bus/i2c/devices/<bus>-00<addr>/driver links to the driver.
#include <optional>
#include <string>

namespace headingd::drivers {

// The sysfs root to look in: $HEADINGD_SYSFS_ROOT when set (tests use a fake tree), else "/sys".
std::string sysfs_root();

// The name of the kernel driver bound to the device at `address` on the adapter `bus_path`
// (/dev/i2c-N, or a link to one); nothing when none is, or the adapter's number is unknown.
std::optional<std::string> bound_kernel_driver(const std::string& sysfs, const std::string& bus_path, int address);

// The refusal for a bound driver: what owns the chip and how to hand it over.
std::string kernel_driver_message(const std::string& bus_path, int address, const std::string& driver);

}  // namespace headingd::drivers
