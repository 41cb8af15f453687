#include "dds/shm_cleanup.hpp"

#include <dirent.h>
#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdlib>
#include <set>
#include <vector>

namespace headingd::app {
namespace {

bool ours(int directory_fd, const std::string& name) {
  struct stat info {};
  return fstatat(directory_fd, name.c_str(), &info, AT_SYMLINK_NOFOLLOW) == 0 && S_ISREG(info.st_mode) &&
         info.st_uid == geteuid();
}

std::vector<std::string> entries(DIR* directory) {
  std::vector<std::string> names;
  while (const dirent* entry = readdir(directory)) names.emplace_back(entry->d_name);
  return names;
}

// The low 16 bits of every running process's pid.
std::set<unsigned> running_pid_bits() {
  std::set<unsigned> bits;
  DIR* proc = opendir("/proc");
  if (proc == nullptr) return bits;
  for (const auto& name : entries(proc)) {
    char* end = nullptr;
    const unsigned long pid = std::strtoul(name.c_str(), &end, 10);
    if (end != name.c_str() && *end == '\0') bits.insert(static_cast<unsigned>(pid & 0xFFFFU));
  }
  closedir(proc);
  return bits;
}

// fast_datasharing_01.0f.HH.HH.PP.PP.xx.xx...: the pid bits (little-endian), or -1.
long datasharing_pid_bits(const std::string& name) {
  const std::string prefix = "fast_datasharing_";
  if (name.rfind(prefix, 0) != 0 || name.size() < prefix.size() + 17) return -1;
  const auto byte = [&](std::size_t index) -> long {
    const std::string text = name.substr(prefix.size() + 3 * index, 2);
    char* end = nullptr;
    const long value = std::strtol(text.c_str(), &end, 16);
    return end == text.c_str() + 2 ? value : -1;
  };
  const long low = byte(4), high = byte(5);
  return low < 0 || high < 0 ? -1 : low | (high << 8);
}

}  // namespace

std::size_t remove_stale_fastdds_files(const std::string& directory) {
  const int directory_fd = open(directory.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (directory_fd < 0) return 0;
  DIR* listing = fdopendir(dup(directory_fd));
  if (listing == nullptr) {
    close(directory_fd);
    return 0;
  }
  const std::vector<std::string> names = entries(listing);
  closedir(listing);
  std::size_t removed = 0;
  const auto remove = [&](const std::string& name) {
    if (ours(directory_fd, name) && unlinkat(directory_fd, name.c_str(), 0) == 0) ++removed;
  };
  const std::string lock_suffix = "_el";
  for (const auto& name : names) {
    if (name.rfind("fastrtps_", 0) != 0 || name.size() <= lock_suffix.size() ||
        name.compare(name.size() - lock_suffix.size(), lock_suffix.size(), lock_suffix) != 0 ||
        !ours(directory_fd, name))
      continue;
    const int lock_fd = openat(directory_fd, name.c_str(), O_RDWR | O_NOFOLLOW | O_CLOEXEC);
    if (lock_fd < 0) continue;
    if (flock(lock_fd, LOCK_EX | LOCK_NB) == 0) {  // nobody holds it: the owner is gone
      const std::string segment = name.substr(0, name.size() - lock_suffix.size());
      remove(segment);
      remove("sem." + segment + "_mutex");
      remove(name);
    }
    close(lock_fd);
  }
  std::set<unsigned> running;
  bool listed = false;
  for (const auto& name : names) {
    const long bits = datasharing_pid_bits(name);
    if (bits < 0 || !ours(directory_fd, name)) continue;
    if (!listed) {
      running = running_pid_bits();
      listed = true;
    }
    if (running.count(static_cast<unsigned>(bits)) == 0) remove(name);
  }
  close(directory_fd);
  return removed;
}

}  // namespace headingd::app
