// The floor a replay is measured against: map a recording and parse every field of every
// sample line with std::from_chars, nothing else (no checks, no estimator, no output). What
// `headingd replay` costs beyond this is the price of everything else it does.
#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

namespace {

struct Parsed {
  std::size_t lines = 0;
  double checksum = 0.0;  // keeps the parse from being optimised away
};

Parsed parse_all(const char* data, std::size_t size) {
  Parsed out;
  const char* p = data;
  const char* end = data + size;
  bool header_seen = false;
  while (p < end) {
    const auto* newline = static_cast<const char*>(std::memchr(p, '\n', static_cast<std::size_t>(end - p)));
    const char* line_end = newline != nullptr ? newline : end;
    if (*p == '#' || !header_seen) {
      header_seen = header_seen || *p != '#';
      p = line_end + 1;
      continue;
    }
    const char* field = p;
    while (field < line_end) {
      double value = 0.0;
      const auto result = std::from_chars(field, line_end, value);
      out.checksum += value;
      field = result.ptr + 1;  // past the comma
    }
    ++out.lines;
    p = line_end + 1;
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  const long runs = argc == 3 ? std::strtol(argv[2], nullptr, 10) : 3;
  if (argc < 2 || argc > 3 || runs < 1) {
    std::fprintf(stderr, "usage: parse_baseline RECORDING.csv [RUNS]\n");
    return 64;
  }
  const int fd = ::open(argv[1], O_RDONLY | O_CLOEXEC);
  struct stat info {};
  if (fd < 0 || ::fstat(fd, &info) != 0 || info.st_size <= 0) {
    std::perror(argv[1]);
    return 66;
  }
  const auto size = static_cast<std::size_t>(info.st_size);
  std::vector<double> seconds;
  Parsed parsed;
  for (long run = 0; run < runs; ++run) {
    const auto start = std::chrono::steady_clock::now();
    void* map = ::mmap(nullptr, size, PROT_READ, MAP_PRIVATE, fd, 0);
    if (map == MAP_FAILED) {
      std::perror("mmap");
      return 71;
    }
    ::madvise(map, size, MADV_SEQUENTIAL);
    parsed = parse_all(static_cast<const char*>(map), size);
    ::munmap(map, size);
    seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  ::close(fd);
  std::sort(seconds.begin(), seconds.end());
  std::printf(
      "baseline parse (mmap + from_chars, every field): %.2f s for %zu sample lines (median of %ld; checksum %.6g)\n",
      seconds[seconds.size() / 2], parsed.lines, runs, parsed.checksum);
  return 0;
}
