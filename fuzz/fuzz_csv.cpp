// libFuzzer target: the recording reader (native CSV and EuRoC, told apart by the header; plain,
// zstd or gzip, told apart by the magic number) on arbitrary bytes. Any input must end in samples
// or an InputError, never a crash or a hang.
#include <cstdio>
#include <vector>

#include "io/csv_replay.hpp"

extern "C" int LLVMFuzzerTestOneInput(const unsigned char* data, std::size_t size) {
  std::vector<unsigned char> copy(data, data + size);  // fmemopen wants a writable buffer
  std::FILE* file = size > 0 ? fmemopen(copy.data(), size, "rb") : fmemopen(nullptr, 1, "w+b");
  if (file == nullptr) return 0;
  try {
    headingd::drivers::CsvReplaySource source(file, "fuzz.csv");
    std::vector<headingd::core::Sample> batch(64);
    while (source.read(batch) > 0) {
    }
  } catch (const headingd::drivers::InputError&) {
  } catch (const headingd::drivers::OpenError&) {
  }
  return 0;
}
