#include "hw/kernel_binding.hpp"

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <system_error>

namespace headingd::drivers {
namespace {

// "1-006b" for /dev/i2c-1, address 0x6B: the kernel's name for an I2C client.
std::optional<std::string> client_name(const std::string& bus_path, int address) {
  std::error_code error;
  std::filesystem::path path = std::filesystem::weakly_canonical(bus_path, error);
  if (error) path = bus_path;
  const std::string name = path.filename().string();
  const std::string prefix = "i2c-";
  if (name.rfind(prefix, 0) != 0 || name.size() == prefix.size()) return std::nullopt;
  const std::string number = name.substr(prefix.size());
  if (number.find_first_not_of("0123456789") != std::string::npos || number.size() > 6) return std::nullopt;
  char text[32];
  std::snprintf(text, sizeof text, "%s-%04x", number.c_str(), static_cast<unsigned>(address));
  return std::string(text);
}

}  // namespace

std::string sysfs_root() {
  const char* root = std::getenv("HEADINGD_SYSFS_ROOT");
  return root != nullptr && *root != '\0' ? root : "/sys";
}

std::optional<std::string> bound_kernel_driver(const std::string& sysfs, const std::string& bus_path, int address) {
  const auto client = client_name(bus_path, address);
  if (!client) return std::nullopt;
  std::error_code error;
  const auto link = std::filesystem::path(sysfs) / "bus/i2c/devices" / *client / "driver";
  const auto target = std::filesystem::read_symlink(link, error);
  if (error) return std::nullopt;  // no driver bound (or no such client)
  return target.filename().string();
}

std::string kernel_driver_message(const std::string& bus_path, int address, const std::string& driver) {
  const std::string client = client_name(bus_path, address).value_or("?");
  char text[640];
  std::snprintf(text, sizeof text,
                "%s address 0x%02X is bound to the kernel driver '%s' (I2C client %s), which programs the chip "
                "itself; headingd will not share it. Unbind it (echo %s > /sys/bus/i2c/drivers/%s/unbind), or "
                "remove the device-tree node or blacklist the module (st_gyro_i2c) for good",
                bus_path.c_str(), static_cast<unsigned>(address), driver.c_str(), client.c_str(), client.c_str(),
                driver.c_str());
  return text;
}

}  // namespace headingd::drivers
