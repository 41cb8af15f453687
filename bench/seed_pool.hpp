#pragma once
// Runs one function per seed on every core, results in seed order: the randomized benches'
// figures do not depend on how many cores ran them.
#include <algorithm>
#include <atomic>
#include <cstdint>
#include <thread>
#include <vector>

namespace headingd::bench {

// `run(seed)` for seeds first_seed .. first_seed + count - 1.
template <typename Result, typename Run>
std::vector<Result> run_seeds(long count, long first_seed, Run run) {
  std::vector<Result> results(static_cast<std::size_t>(count));
  std::atomic<long> next{0};
  std::vector<std::thread> workers;
  for (unsigned w = 0; w < std::max(1u, std::thread::hardware_concurrency()); ++w) {
    workers.emplace_back([&] {
      for (long k = next++; k < count; k = next++)
        results[static_cast<std::size_t>(k)] = run(static_cast<std::uint64_t>(k + first_seed));
    });
  }
  for (auto& worker : workers) worker.join();
  return results;
}

}  // namespace headingd::bench
