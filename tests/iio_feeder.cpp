// Stands in for a kernel IIO gyro driver in CLI tests and benchmarks: builds a fake IIO tree
// under ROOT and writes the gyro simulator's scenario into its /dev/iio:deviceN FIFO.
//   iio_feeder ROOT st16|be32|swapped SCENARIO SEED SECONDS [paced]
// Prints "ready" once the tree exists; the FIFO open then waits for a reader. Exits when all
// scans are written or the reader has gone.
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

#include "sim/gyro_simulator.hpp"
#include "sim/iio_fake.hpp"

using namespace headingd;

int main(int argc, char** argv) {
  if (argc < 6) {
    std::fprintf(stderr, "usage: iio_feeder ROOT st16|be32|swapped SCENARIO SEED SECONDS [paced]\n");
    return 64;
  }
  std::signal(SIGPIPE, SIG_IGN);  // a reader that leaves ends us through write()'s EPIPE
  const std::string layout_name = argv[2];
  drivers::FakeIioOptions options;
  options.root = argv[1];
  options.layout = layout_name == "be32"      ? drivers::FakeIioLayout::Be32Shift
                   : layout_name == "swapped" ? drivers::FakeIioLayout::SwappedMount
                                              : drivers::FakeIioLayout::St16;
  const auto seed = std::strtoull(argv[4], nullptr, 10);
  const double seconds = std::strtod(argv[5], nullptr);
  const bool paced = argc > 6 && std::string(argv[6]) == "paced";
  auto scenario = drivers::build_scenario(argv[3], seed, seconds / 3600.0);
  if (!scenario) {
    std::fprintf(stderr, "iio_feeder: unknown scenario %s\n", argv[3]);
    return 64;
  }
  drivers::FakeIioTree tree(options);
  tree.create();
  std::printf("ready\n");
  std::fflush(stdout);
  drivers::GyroSimulator sim(*scenario, seed);
  drivers::FakeIioWriter writer(tree);
  const double rate_hz = scenario->noise.rate_hz;
  const std::size_t bytes = tree.layout().scan_bytes();
  constexpr std::size_t kBurst = 16;  // the default [sensor.iio] watermark
  std::vector<std::uint8_t> burst;
  const auto start = std::chrono::steady_clock::now();
  for (std::uint64_t i = 0; !sim.done(); ++i) {
    core::Sample s;
    drivers::TruthPoint t;
    sim.step(s, t);
    const auto t_ns = 1'000'000'000'000 + static_cast<std::int64_t>(static_cast<double>(i) * 1e9 / rate_hz);
    const std::size_t at = burst.size();
    burst.resize(at + bytes);
    tree.encode(s.rate_dps, t_ns, std::span(burst).subspan(at, bytes));
    if (burst.size() < kBurst * bytes) continue;
    if (paced)
      std::this_thread::sleep_until(start + std::chrono::duration<double>(static_cast<double>(i + 1) / rate_hz));
    if (!writer.write(burst)) return 0;
    burst.clear();
  }
  if (!burst.empty()) writer.write(burst);
  return 0;
}
