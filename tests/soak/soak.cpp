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

#include "app/live_source.hpp"
#include "core/estimator.hpp"
#include "dds/dds_node.hpp"
#include "dds/dds_participant.hpp"
#include "headingdPubSubTypes.h"
#include "pipeline/dds_sink.hpp"
#include "pipeline/pipeline.hpp"

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
    app::apply_transport(settings, qos);
    sub->create_datareader(topic, qos);
    for (int i = 0; i < 20 && !done.load(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(25));
    app::delete_participant(participant);
    ++cycles;
  }
}

struct Injected {
  std::uint64_t nack_transactions = 0, timeout_transactions = 0, resets = 0, stalls = 0, stucks = 0;
};

// Injects a random fault every 30-120 simulated seconds and watches the heading and memory.
class FaultsAndChecks final : public pipeline::Sink {
 public:
  FaultsAndChecks(drivers::L3gd20hSimulator& sim, std::uint64_t seed, double end_s)
      : sim_(sim), rng_(seed), end_s_(end_s) {}

  void add(const core::Sample& sample, const core::Estimate& e, const core::Estimator& /*estimator*/) override {
    if (std::isnan(first_t_)) first_t_ = sample.t_s;
    t_ = sample.t_s;
    max_step = std::max(max_step, std::abs(e.heading_deg - previous_heading_));
    max_abs = std::max(max_abs, std::abs(e.heading_deg));
    previous_heading_ = e.heading_deg;
  }

  void batch_done(const core::Estimator& /*estimator*/, const core::SampleSource& /*source*/) override {
    const double elapsed = t_ - first_t_;
    if (elapsed >= next_fault_s_) {
      next_fault_s_ = elapsed + gap_s_(rng_);
      inject();
    }
    if (rss_after_warmup < 0 && elapsed > 0.1 * end_s_) rss_after_warmup = rss_kb();
    rss_max = std::max(rss_max, rss_kb());
    if (elapsed > (progress_ + 1) * 3600.0) {
      ++progress_;
      std::printf("  %2d h simulated: heading %+.3f deg, RSS %ld kB\n", progress_, previous_heading_, rss_kb());
      std::fflush(stdout);
    }
  }

  Injected injected;
  double max_step = 0.0, max_abs = 0.0;
  long rss_after_warmup = -1, rss_max = 0;

 private:
  void inject() {
    switch (kind_(rng_)) {
      case 0: {
        const int count = nacks_(rng_);  // within the retries
        sim_.inject_nack(count);
        injected.nack_transactions += static_cast<std::uint64_t>(count);
        break;
      }
      case 1:
        sim_.inject_timeout(6);  // past the retries: the chip is set up again
        injected.timeout_transactions += 6;
        break;
      case 2:
        sim_.inject_reset();
        ++injected.resets;
        break;
      case 3:
        sim_.inject_stall(200'000'000);
        ++injected.stalls;
        break;
      default:
        sim_.inject_stuck(3'000'000'000);
        ++injected.stucks;
        break;
    }
  }

  drivers::L3gd20hSimulator& sim_;
  std::mt19937_64 rng_;
  std::uniform_real_distribution<double> gap_s_{30.0, 120.0};
  std::uniform_int_distribution<int> kind_{0, 4}, nacks_{1, 3};
  double end_s_;
  double next_fault_s_ = 60.0;
  double first_t_ = NAN, t_ = 0.0;
  double previous_heading_ = 0.0;
  int progress_ = 0;
};

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
  std::unique_ptr<app::DdsNode> node;
  std::atomic<bool> done{false};
  std::atomic<int> churn_cycles{0};
  std::thread churner;
  if (dds) {
    node = std::make_unique<app::DdsNode>(settings);
    churner = std::thread(churn, std::cref(settings), std::cref(done), std::ref(churn_cycles));
  }

  pipeline::PipelineOptions options;
  options.duration_s = hours * 3600.0;
  pipeline::Pipeline line(driver, std::make_unique<core::Estimator>(), options);
  FaultsAndChecks checks(*source.simulator(), seed, hours * 3600.0);
  line.add_sink(checks);
  std::optional<pipeline::DdsSink> publisher;
  if (node) line.add_sink(publisher.emplace(*node, driver, pipeline::StampClock::FirstSample));
  const pipeline::Outcome outcome = line.run();
  done = true;
  if (churner.joinable()) churner.join();
  const long rss_end = rss_kb();
  node.reset();
  const Injected& injected = checks.injected;
  const double max_step = checks.max_step, max_abs = checks.max_abs;
  const long rss_after_warmup = checks.rss_after_warmup, rss_max = checks.rss_max;

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
  check(outcome.ending == pipeline::Ending::Duration, "ran its full length");
  std::printf("%s\n", ok ? "soak: all checks passed" : "soak: FAILED");
  return ok ? 0 : 1;
}
