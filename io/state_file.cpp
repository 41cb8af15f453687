#include "io/state_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <vector>

#include "core/estimator.hpp"
#include "core/scale_factor.hpp"

namespace headingd::app {
namespace {

constexpr const char* kMagic = "# headingd state";
constexpr int kVersion = 1;
constexpr off_t kMaxStateBytes = off_t{64} * 1024;  // ours are about 1 KiB

// FNV-1a, 64 bit: enough to notice truncation and corruption (not an attack).
std::uint64_t checksum(const std::string& text) {
  std::uint64_t h = 1469598103934665603ull;
  for (const char ch : text) {
    const auto c = static_cast<unsigned char>(ch);
    h ^= c;
    h *= 1099511628211ull;
  }
  return h;
}

std::string numbers(std::initializer_list<double> values) {
  std::string out;
  char buffer[40];
  for (double v : values) {
    std::snprintf(buffer, sizeof buffer, "%.17g", v);
    out += (out.empty() ? "" : " ") + std::string(buffer);
  }
  return out;
}

void check(bool ok, const std::string& path, const char* what) {
  if (!ok) throw StateError("cannot write state " + path + ": " + what + ": " + std::strerror(errno));
}

}  // namespace

std::string format_state(const SavedState& s) {
  std::ostringstream body;
  body << kMagic << " v" << kVersion << "\n";
  body << "saved_unix_s=" << numbers({s.saved_unix_s}) << "\n";
  body << "bias_dps=" << numbers({s.bias_dps.x(), s.bias_dps.y(), s.bias_dps.z()}) << "\n";
  body << "bias_sigma_dps=" << numbers({s.bias_sigma_dps.x(), s.bias_sigma_dps.y(), s.bias_sigma_dps.z()}) << "\n";
  body << "temp_c=" << numbers({s.temp_c}) << "\n";
  // Optional (files from before it lack it; their temp_c is nan): where the bias was measured.
  if (!std::isnan(s.bias_measured_temp_c)) body << "bias_measured_temp_c=" << numbers({s.bias_measured_temp_c}) << "\n";
  body << "sigma_still_dps=" << numbers({s.sigma_still_dps.x(), s.sigma_still_dps.y(), s.sigma_still_dps.z()}) << "\n";
  body << "arw_dps_rt_hz=" << numbers({s.arw_dps_rt_hz.x(), s.arw_dps_rt_hz.y(), s.arw_dps_rt_hz.z()}) << "\n";
  // Optional (files from before it lack it): heading, its variance (nan: none) and fix offset.
  if (std::isfinite(s.heading_deg))
    body << "heading_deg=" << numbers({s.heading_deg, s.heading_variance_deg2, s.heading_fix_offset_deg}) << "\n";
  // Optional too: the z scale factor learned from heading fixes, and its sigma.
  if (!std::isnan(s.scale_z_sigma)) body << "scale_z=" << numbers({s.scale_z, s.scale_z_sigma}) << "\n";
  for (int a = 0; a < 3; ++a) {
    const auto& t = s.temperature_sums[static_cast<std::size_t>(a)];
    body << "temperature_model_"
         << "xyz"[a] << "=" << s.temperature_points[static_cast<std::size_t>(a)] << " "
         << numbers({t.normal(0, 0), t.normal(0, 1), t.normal(0, 2), t.normal(1, 1), t.normal(1, 2), t.normal(2, 2),
                     t.rhs(0), t.rhs(1), t.rhs(2), t.yy, t.weight})
         << "\n";
  }
  return seal_state(body.str());
}

std::string seal_state(const std::string& body) {
  char line[48];
  std::snprintf(line, sizeof line, "checksum=%016llx\n", static_cast<unsigned long long>(checksum(body)));
  return body + line;
}

SavedState parse_state(const std::string& text, const std::string& name) {
  const auto fail = [&](const std::string& why) -> void {
    throw StateError("state file " + name + ": " + why + "; ignored");
  };
  if (text.rfind(kMagic, 0) != 0) fail("not a headingd state file");
  const auto sum_at = text.rfind("checksum=");
  if (sum_at == std::string::npos) fail("truncated (no checksum)");
  const std::string body = text.substr(0, sum_at);
  std::uint64_t stored = 0;
  const char* digits = text.data() + sum_at + std::strlen("checksum=");
  const char* digits_end = std::min(digits + 16, text.data() + text.size());
  const auto parsed = std::from_chars(digits, digits_end, stored, 16);
  if (parsed.ec != std::errc{} || parsed.ptr == digits || stored != checksum(body))
    fail("checksum mismatch (corrupt or truncated)");
  std::map<std::string, std::vector<double>> fields;
  std::istringstream in(body);
  std::string line;
  std::getline(in, line);
  if (line != std::string(kMagic) + " v" + std::to_string(kVersion)) fail("unsupported version: '" + line + "'");
  while (std::getline(in, line)) {
    const auto eq = line.find('=');
    if (eq == std::string::npos) fail("malformed line '" + line + "'");
    std::istringstream values(line.substr(eq + 1));
    std::vector<double> v;
    for (std::string token; values >> token;) {
      char* end = nullptr;
      const double x = std::strtod(token.c_str(), &end);  // also reads "nan"
      if (end == token.c_str() || *end != '\0')
        fail("field " + line.substr(0, eq) + ": '" + token + "' is not a number");
      v.push_back(x);
    }
    fields[line.substr(0, eq)] = v;
  }
  const auto need = [&](const std::string& key, std::size_t n) -> const std::vector<double>& {
    const auto it = fields.find(key);
    if (it == fields.end() || it->second.size() != n) fail("field " + key + " missing or malformed");
    return it->second;
  };
  SavedState s;
  s.saved_unix_s = need("saved_unix_s", 1)[0];
  const auto& b = need("bias_dps", 3);
  const auto& sg = need("bias_sigma_dps", 3);
  s.bias_dps = core::Vec3(b[0], b[1], b[2]);
  s.bias_sigma_dps = core::Vec3(sg[0], sg[1], sg[2]);
  if (!s.bias_dps.allFinite() || !s.bias_sigma_dps.allFinite() || (s.bias_sigma_dps.array() < 0).any() ||
      s.bias_dps.cwiseAbs().maxCoeff() > 100.0 || s.bias_sigma_dps.maxCoeff() > 100.0)
    fail("bias values out of range");
  const auto temperature = [&](const std::string& key) {
    const double t = need(key, 1)[0];
    if (!std::isnan(t) && !(t >= core::kMinPlausibleTempC && t <= core::kMaxPlausibleTempC))
      fail("field " + key + ": temperature out of range");
    return t;
  };
  s.temp_c = temperature("temp_c");
  if (fields.count("bias_measured_temp_c") != 0) s.bias_measured_temp_c = temperature("bias_measured_temp_c");
  const auto& ss = need("sigma_still_dps", 3);
  const auto& arw = need("arw_dps_rt_hz", 3);
  s.sigma_still_dps = core::Vec3(ss[0], ss[1], ss[2]);
  s.arw_dps_rt_hz = core::Vec3(arw[0], arw[1], arw[2]);
  if (const auto it = fields.find("heading_deg"); it != fields.end()) {
    const auto& h = need("heading_deg", 3);
    // An unwrapped heading of a million degrees is thousands of turns: beyond that, corrupt.
    const bool variance_ok = std::isnan(h[1]) || (h[1] >= 0.0 && h[1] <= 1e6);
    if (!std::isfinite(h[0]) || std::abs(h[0]) > 1e7 || !variance_ok || !std::isfinite(h[2]) || std::abs(h[2]) > 1e7)
      fail("heading values out of range");
    s.heading_deg = h[0];
    s.heading_variance_deg2 = h[1];
    s.heading_fix_offset_deg = h[2];
  }
  if (fields.count("scale_z") != 0) {
    const auto& z = need("scale_z", 2);
    if (!(std::abs(z[0]) <= core::kMaxLearnedScale) || !(z[1] >= 0.0 && z[1] <= 0.5))
      fail("scale_z values out of range");
    s.scale_z = z[0];
    s.scale_z_sigma = z[1];
  }
  for (int a = 0; a < 3; ++a) {
    const auto& t = need(std::string("temperature_model_") + "xyz"[a], 12);
    auto& sums = s.temperature_sums[static_cast<std::size_t>(a)];
    // The count is whole and fits its type: a cast of anything else would be undefined.
    if (!(t[0] >= 0.0 && t[0] <= static_cast<double>(std::numeric_limits<std::uint32_t>::max()) &&
          std::floor(t[0]) == t[0]))
      fail(std::string("field temperature_model_") + "xyz"[a] + ": point count out of range");
    s.temperature_points[static_cast<std::size_t>(a)] = static_cast<std::uint32_t>(t[0]);
    sums.normal << t[1], t[2], t[3], t[2], t[4], t[5], t[3], t[5], t[6];
    sums.rhs << t[7], t[8], t[9];
    sums.yy = t[10];
    sums.weight = t[11];
  }
  // Whatever the estimator would refuse to restore (a still noise of 1e5 dps, a model's sums
  // of inf) is refused here, naming the file, as the checks above do field by field.
  if (const auto problem = core::implausible(s)) fail(*problem);
  return s;
}

void save_state(const std::string& path, const SavedState& state, int crash_after) {
  const std::string text = format_state(state);
  const std::string temp = path + ".tmp";
  const auto step = [&](int k) {
    if (k == crash_after) throw SimulatedCrash{k};
  };
  // The directory decides who may plant files where we write: not everyone.
  const std::string dir =
      std::filesystem::path(path).parent_path().empty() ? "." : std::filesystem::path(path).parent_path().string();
  struct stat dir_info {};
  check(::stat(dir.c_str(), &dir_info) == 0, path, "stat directory");
  if ((dir_info.st_mode & S_IWOTH) != 0)
    throw StateError("state file " + path + ": its directory " + dir + " is writable by others; refusing to write");
  // Created afresh, never through whatever is there: a leftover of a crash or a planted link
  // is removed (unlink takes the link itself, never its target) and the create is exclusive.
  int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
  if (fd < 0 && errno == EEXIST && ::unlink(temp.c_str()) == 0)
    fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
  check(fd >= 0, path, "create temporary file");
  step(0);
  const std::size_t half = text.size() / 2;
  bool ok = ::write(fd, text.data(), half) == static_cast<ssize_t>(half);
  if (!ok) ::close(fd);
  check(ok, path, "write");
  if (crash_after == 1) ::close(fd);
  step(1);
  ok = ::write(fd, text.data() + half, text.size() - half) == static_cast<ssize_t>(text.size() - half);
  if (!ok) ::close(fd);
  check(ok, path, "write");
  if (crash_after == 2) ::close(fd);
  step(2);
  ok = ::fsync(fd) == 0;
  if (!ok) ::close(fd);
  check(ok, path, "fsync");
  if (crash_after == 3) ::close(fd);
  step(3);
  check(::close(fd) == 0, path, "close");
  step(4);
  check(::rename(temp.c_str(), path.c_str()) == 0, path, "rename");
  step(5);
  // The rename is durable only once the directory itself is on disk.
  const int dfd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  check(dfd >= 0, path, "open directory");
  ok = ::fsync(dfd) == 0;
  ::close(dfd);
  check(ok, path, "fsync directory");
  step(6);
}

SavedState load_state(const std::string& path) {
  const auto refuse = [&](const std::string& why) -> void {
    throw StateError("state file " + path + ": " + why + "; starting without saved state");
  };
  // Non-blocking, so a FIFO planted there cannot hold up the start; then only a regular file
  // of a sane size is read (a device such as /dev/zero would never end).
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) refuse(std::strerror(errno));
  struct stat info {};
  std::string text;
  const bool regular = ::fstat(fd, &info) == 0 && S_ISREG(info.st_mode);
  if (regular && info.st_size <= kMaxStateBytes) {
    text.resize(static_cast<std::size_t>(info.st_size));
    std::size_t got = 0;
    while (got < text.size()) {
      const ssize_t n = ::read(fd, text.data() + got, text.size() - got);
      if (n <= 0) break;
      got += static_cast<std::size_t>(n);
    }
    text.resize(got);
  }
  ::close(fd);
  if (!regular) refuse("not a regular file");
  if (info.st_size > kMaxStateBytes) refuse("larger than any state file (" + std::to_string(info.st_size) + " bytes)");
  return parse_state(text, path);
}

}  // namespace headingd::app
