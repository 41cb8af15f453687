// Soak: the live pipeline (L3GD20H driver on the simulated chip, auto estimator, DDS node)
// for many simulated hours with random faults — NACKs, bus timeouts, chip resets, late reads
// (FIFO overruns), stuck output — while DDS subscribers come and go. Checks that nothing
// throws, memory stays flat after warm-up, the heading of the (still) platform stays
// continuous, and every injected fault is counted.
// Usage: soak [--hours H] [--seed N] [--no-dds] [--profile FILE.xml]
#include <atomic>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/subscriber/qos/DataReaderQos.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>
#include <fstream>
#include <optional>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "core/estimator.hpp"
#include "daemon/dds_node.hpp"
#include "daemon/dds_participant.hpp"
#include "daemon/live_source.hpp"
#include "headingdPubSubTypes.h"

using namespace headingd;

namespace {

long rss_kb() {
  std::ifstream status("/proc/self/status");
  for (std::string line; std::getline(status, line);)
    if (line.rfind("VmRSS:", 0) == 0) return std::strtol(line.c_str() + 6, nullptr, 10);
  return -1;
}

// Subscribers joining and leaving, in real time, for as long as the soak runs.
void churn(const app::DdsSettings& settings, const std::atomic<bool>& done, std::atomic<int>& cycles) {
  using namespace eprosima::fastdds::dds;
  while (!done.load()) {
    auto* participant = app::create_participant(settings, "soak-subscriber");
    TypeSupport type(new headingd::msg::OrientationPubSubType());
    type.register_type(participant);
    auto* topic =
        participant->create_topic(app::topic_name(settings, "orientation"), type.get_type_name(), TOPIC_QOS_DEFAULT);
    auto* sub = participant->create_subscriber(SUBSCRIBER_QOS_DEFAULT);
    DataReaderQos qos = DATAREADER_QOS_DEFAULT;
    qos.reliability().kind = BEST_EFFORT_RELIABILITY_QOS;
    sub->create_datareader(topic, qos);
    for (int i = 0; i < 20 && !done.load(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(25));
    app::delete_participant(participant);
    ++cycles;
  }
}

}  // namespace

// A whole positive number from the command line, or nothing.
std::optional<double> positive_number(const char* text) {
  char* end = nullptr;
  const double value = std::strtod(text, &end);
  if (end == text || *end != '\0' || !(value > 0.0)) return std::nullopt;
  return value;
}

std::optional<std::uint64_t> whole_number(const char* text) {
  std::uint64_t value = 0;
  const char* end = text + std::strlen(text);
  const auto parsed = std::from_chars(text, end, value);
  if (parsed.ec != std::errc{} || parsed.ptr != end || parsed.ptr == text) return std::nullopt;
  return value;
}

int main(int argc, char** argv) {
  double hours = 24.0;
  std::uint64_t seed = 1;
  bool dds = true;
  app::DdsSettings settings;
  settings.domain_id = 47;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--hours" && i + 1 < argc && positive_number(argv[i + 1]))
      hours = *positive_number(argv[++i]);
    else if (a == "--seed" && i + 1 < argc && whole_number(argv[i + 1]))
      seed = *whole_number(argv[++i]);
    else if (a == "--no-dds")
      dds = false;
    else if (a == "--profile" && i + 1 < argc)
      settings.profiles_xml = argv[++i];
    else {
      std::fprintf(stderr, "usage: soak [--hours H] [--seed N] [--no-dds] [--profile FILE.xml]\n");
      return 64;
    }
  }
  app::SensorOptions sensor;
  sensor.simulated_chip = "still";
  sensor.sim_seed = seed;
  app::LiveSource source(sensor);
  auto& driver = source.driver();
  driver.set_logger([](int, const std::string&, const std::string&) {});  // counted, not printed
  auto* sim = source.simulator();
  core::Estimator estimator;
  std::unique_ptr<app::DdsNode> node;
  std::atomic<bool> done{false};
  std::atomic<int> churn_cycles{0};
  std::thread churner;
  if (dds) {
    node = std::make_unique<app::DdsNode>(settings);
    churner = std::thread(churn, std::cref(settings), std::cref(done), std::ref(churn_cycles));
  }

  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> gap_s(30.0, 120.0);
  std::uniform_int_distribution<int> kind(0, 4), nacks(1, 3);
  struct Injected {
    std::uint64_t nack_transactions = 0, timeout_transactions = 0, resets = 0, stalls = 0, stucks = 0;
  } injected;

  const double end_s = hours * 3600.0;
  double next_fault_s = 60.0;
  double previous_heading = 0.0, max_step = 0.0, max_abs = 0.0;
  long rss_after_warmup = -1, rss_max = 0;
  std::vector<core::Sample> batch(64);
  double t = 0.0, first_t = NAN;
  app::StatusReport report;
  int progress = 0;
  while (t - (std::isnan(first_t) ? 0.0 : first_t) < end_s) {
    const std::size_t n = driver.read(batch);
    for (std::size_t i = 0; i < n; ++i) {
      if (std::isnan(first_t)) first_t = batch[i].t_s;
      const auto& e = estimator.update(batch[i]);
      max_step = std::max(max_step, std::abs(e.heading_deg - previous_heading));
      max_abs = std::max(max_abs, std::abs(e.heading_deg));
      previous_heading = e.heading_deg;
      if (node) node->publish(e, estimator, report, 0.0);
    }
    t = batch[n - 1].t_s;
    const double elapsed = t - first_t;
    if (elapsed >= next_fault_s) {
      next_fault_s = elapsed + gap_s(rng);
      switch (kind(rng)) {
        case 0: {
          const int count = nacks(rng);  // within the retries
          sim->inject_nack(count);
          injected.nack_transactions += static_cast<std::uint64_t>(count);
          break;
        }
        case 1:
          sim->inject_timeout(6);  // past the retries: the chip is set up again
          injected.timeout_transactions += 6;
          break;
        case 2:
          sim->inject_reset();
          ++injected.resets;
          break;
        case 3:
          sim->inject_stall(200'000'000);
          ++injected.stalls;
          break;
        default:
          sim->inject_stuck(3'000'000'000);
          ++injected.stucks;
          break;
      }
    }
    if (rss_after_warmup < 0 && elapsed > 0.1 * end_s) rss_after_warmup = rss_kb();
    rss_max = std::max(rss_max, rss_kb());
    if (elapsed > (progress + 1) * 3600.0) {
      ++progress;
      std::printf("  %2d h simulated: heading %+.3f deg, RSS %ld kB\n", progress, previous_heading, rss_kb());
      std::fflush(stdout);
    }
  }
  done = true;
  if (churner.joinable()) churner.join();
  const long rss_end = rss_kb();
  node.reset();

  const auto& c = driver.counters();
  std::printf("soak: %.1f simulated hours, %llu samples, %d subscriber join/leave cycles\n", hours,
              static_cast<unsigned long long>(c.samples), churn_cycles.load());
  std::printf(
      "  injected: %llu NACKed and %llu timed-out transactions, %llu chip resets, %llu late reads, %llu stuck "
      "periods\n",
      static_cast<unsigned long long>(injected.nack_transactions),
      static_cast<unsigned long long>(injected.timeout_transactions), static_cast<unsigned long long>(injected.resets),
      static_cast<unsigned long long>(injected.stalls), static_cast<unsigned long long>(injected.stucks));
  std::printf(
      "  counted:  %llu bus errors, %llu chip resets, %llu overruns (%llu samples lost), %llu stuck events, %llu "
      "recoveries\n",
      static_cast<unsigned long long>(c.bus_errors), static_cast<unsigned long long>(c.chip_resets),
      static_cast<unsigned long long>(c.overruns), static_cast<unsigned long long>(c.lost_samples),
      static_cast<unsigned long long>(c.stuck_events), static_cast<unsigned long long>(c.recoveries));
  std::printf("  RSS after warm-up %ld kB, max %ld kB, end %ld kB (growth %ld kB)\n", rss_after_warmup, rss_max,
              rss_end, rss_max - rss_after_warmup);
  std::printf("  heading: largest step between samples %.4f deg, largest |heading| %.3f deg\n", max_step, max_abs);

  bool ok = true;
  const auto check = [&](bool condition, const char* what) {
    if (!condition) {
      std::printf("FAIL: %s\n", what);
      ok = false;
    }
  };
  check(c.bus_errors == injected.nack_transactions + injected.timeout_transactions, "every failed transaction counted");
  check(c.chip_resets == injected.resets, "every chip reset counted");
  check(c.overruns == injected.stalls, "every late read counted as an overrun");
  check(c.stuck_events == injected.stucks, "every stuck period counted");
#if defined(__SANITIZE_ADDRESS__)
  // AddressSanitizer keeps freed memory in quarantine: RSS says nothing about leaks here
  // (LeakSanitizer does); the figure is checked in the optimised build.
  std::printf("  (RSS not checked under AddressSanitizer)\n");
#else
  check(rss_max - rss_after_warmup < 1024, "RSS growth under 1 MB after warm-up");
#endif
  check(max_step < 0.5, "heading continuous across faults");
  std::printf("%s\n", ok ? "soak: all checks passed" : "soak: FAILED");
  return ok ? 0 : 1;
}
