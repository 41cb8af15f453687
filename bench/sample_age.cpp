// Sample age at the subscriber: from the chip's sampling instant (the time the driver
// reconstructs from the watermark edge) to the moment a subscriber in another process receives
// the Orientation message carrying that sample, over Fast DDS on loopback, for FIFO watermarks
// 1, 2, 4, 6, 8 (the default), 10 and 16 at 400 Hz. The chip is the register-level simulator in
// real time: real FIFO timing, and every I2C transfer takes its time on the wire (bytes x 9
// bits / 400 kHz) before the call returns. The sampling instant is taken on the simulator's
// clock anchored to the steady clock, which both processes share, not from the published stamp
// (that maps sample time to wall time by the least delay seen, and so leaves that delay out).
// Also the publishing process's CPU share after its first second (the simulator's pacing
// included: an upper bound).
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/subscriber/qos/DataReaderQos.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>
#include <thread>
#include <vector>

#include "core/estimator.hpp"
#include "dds/dds_node.hpp"
#include "dds/dds_participant.hpp"
#include "headingdPubSubTypes.h"
#include "hw/l3gd20h.hpp"
#include "pipeline/dds_sink.hpp"
#include "pipeline/pipeline.hpp"
#include "sim/l3gd20h_sim.hpp"

using namespace headingd;
using namespace eprosima::fastdds::dds;

namespace {

double g_seconds = 15.0;  // per run; bench/sample_age.sh runs each watermark three times, interleaved

double steady_s() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

// The subscriber's side: each Orientation's sequence number and its arrival on the steady clock
// (CLOCK_MONOTONIC, one clock for both processes).
struct Arrival {
  double seq = 0.0;
  double steady_s = 0.0;
};

class Arrivals : public DataReaderListener {
 public:
  std::vector<Arrival> got;
  void on_data_available(DataReader* reader) override {
    headingd::msg::Orientation m;
    SampleInfo info;
    while (reader->take_next_sample(&m, &info) == ReturnCode_t::RETCODE_OK) {
      if (info.valid_data) got.push_back({static_cast<double>(m.seq()), steady_s()});
    }
  }
};

double cpu_s(int who = RUSAGE_SELF) {
  rusage usage{};
  getrusage(who, &usage);
  return static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
         static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec) * 1e-6;
}

// The publisher's side, after the DdsSink: which sample each Orientation carried (its
// simulated time), and the process's CPU time once the first second (start-up, discovery) is
// over: the CPU share is the steady state's, over the same span as the ages.
class PublishedSamples final : public pipeline::Sink {
 public:
  explicit PublishedSamples(const app::DdsNode& node) : node_(node) {}
  void add(const core::Sample& sample, const core::Estimate&, const core::Estimator&) override {
    if (first_t_s < 0.0) first_t_s = sample.t_s;
    if (!steady && sample.t_s >= first_t_s + 1.0) {
      steady = true;
      steady_cpu_s = cpu_s();
      steady_thread_cpu_s = cpu_s(RUSAGE_THREAD);
      steady_since = std::chrono::steady_clock::now();
    }
    note();
  }
  void batch_done(const core::Estimator&, const core::SampleSource&) override { note(); }

  std::vector<double> t_s_by_seq{0.0};  // index: sequence number (from 1)
  double first_t_s = -1.0;
  bool steady = false;
  double steady_cpu_s = 0.0, steady_thread_cpu_s = 0.0;
  std::chrono::steady_clock::time_point steady_since;

 private:
  void note() {
    while (t_s_by_seq.size() <= node_.orientation_sent()) t_s_by_seq.push_back(node_.orientation_sample_t_s());
  }
  const app::DdsNode& node_;
};

int subscriber(const app::DdsSettings& settings, int out_fd) {
  auto* participant = app::create_participant(settings, "age-subscriber");
  TypeSupport type(new headingd::msg::OrientationPubSubType());
  type.register_type(participant);
  auto* topic =
      participant->create_topic(app::topic_name(settings, "orientation"), type.get_type_name(), TOPIC_QOS_DEFAULT);
  auto* sub = participant->create_subscriber(SUBSCRIBER_QOS_DEFAULT);
  Arrivals listener;
  listener.got.reserve(4096);
  DataReaderQos qos = DATAREADER_QOS_DEFAULT;
  qos.reliability().kind = BEST_EFFORT_RELIABILITY_QOS;
  app::apply_transport(settings, qos);
  sub->create_datareader(topic, qos, &listener);
  std::this_thread::sleep_for(std::chrono::duration<double>(g_seconds + 6.0));
  app::delete_participant(participant);
  const auto bytes = static_cast<ssize_t>(listener.got.size() * sizeof(Arrival));
  return write(out_fd, listener.got.data(), static_cast<std::size_t>(bytes)) == bytes ? 0 : 1;
}

double percentile(std::vector<double> v, double p) {
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(p * static_cast<double>(v.size() - 1))];
}

// One watermark: the daemon's pipeline on the real-time chip, a subscriber in a child process.
void measure(int watermark, const std::string& profiles) {
  app::DdsSettings settings{};
  settings.domain_id = 46;
  if (!profiles.empty()) settings.profiles_xml = profiles;
  int fds[2];
  if (pipe(fds) != 0) return;
  const pid_t child = fork();
  if (child == 0) {
    close(fds[0]);
    _exit(subscriber(settings, fds[1]));
  }
  close(fds[1]);
  double cpu = 0.0, thread_cpu = 0.0, wall = 0.0, total_wall = 0.0, anchor_s = 0.0;
  std::vector<double> t_s_by_seq;
  {
    app::DdsNode node(settings);
    node.wait_for_subscribers(10.0);
    drivers::L3gd20hSimulator chip({}, "agv", 1);
    chip.set_realtime(true);
    drivers::L3gd20hSettings driver_settings;
    driver_settings.watermark = watermark;
    drivers::L3gd20h driver(chip, chip, driver_settings);
    driver.start();
    pipeline::PipelineOptions options;
    options.duration_s = g_seconds;
    pipeline::Pipeline line(driver, std::make_unique<core::Estimator>(), options);
    pipeline::DdsSink publisher(node, driver, pipeline::StampClock::FirstSample);  // as the daemon, live
    line.add_sink(publisher);
    PublishedSamples published(node);
    line.add_sink(published);
    const auto start = std::chrono::steady_clock::now();
    line.run();
    total_wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    thread_cpu = cpu_s(RUSAGE_THREAD) - published.steady_thread_cpu_s;
    cpu = cpu_s() - published.steady_cpu_s;
    wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - published.steady_since).count();
    anchor_s = std::chrono::duration<double>(chip.wall_anchor().value().time_since_epoch()).count();
    t_s_by_seq = published.t_s_by_seq;
  }
  std::vector<Arrival> arrivals;
  Arrival buffer[512];
  ssize_t n;
  while ((n = read(fds[0], buffer, sizeof buffer)) > 0)
    arrivals.insert(arrivals.end(), buffer, buffer + n / static_cast<ssize_t>(sizeof(Arrival)));
  close(fds[0]);
  waitpid(child, nullptr, 0);
  // Age: arrival minus the sample's physical instant, the simulator's clock anchored to the
  // steady clock (not the published stamp, which maps sample time to the wall clock by the least
  // delay seen and so leaves the least delay out). The first second is the start-up.
  std::vector<double> ms;
  std::size_t sent = t_s_by_seq.size() - 1;
  for (const Arrival& a : arrivals) {
    const auto seq = static_cast<std::size_t>(a.seq);
    if (seq < static_cast<std::size_t>(settings.orientation_rate_hz) || seq >= t_s_by_seq.size()) continue;
    ms.push_back((a.steady_s - (anchor_s + t_s_by_seq[seq])) * 1e3);
  }
  if (ms.empty()) {
    std::printf("watermark=%d received=0\n", watermark);
    return;
  }
  // One line per run, fields by name, for bench/sample_age.sh to take medians over runs.
  std::printf(
      "watermark=%d received=%zu sent=%zu rate_hz=%.1f age_p50_ms=%.2f age_p99_ms=%.2f age_max_ms=%.2f cpu_pct=%.3f "
      "thread_cpu_pct=%.3f\n",
      watermark, ms.size(), sent, static_cast<double>(sent) / total_wall, percentile(ms, 0.5), percentile(ms, 0.99),
      percentile(ms, 1.0), 100.0 * cpu / wall, 100.0 * thread_cpu / wall);
  std::fflush(stdout);
}

}  // namespace

// One watermark per process: Fast DDS does not survive a fork after a participant existed, so
// bench/sample_age.sh runs this once per watermark.
int main(int argc, char** argv) {
  char* end = nullptr;
  const long watermark = argc > 1 ? std::strtol(argv[1], &end, 10) : 16;
  if (watermark < 1 || watermark > 30 || (argc > 1 && *end != '\0')) {
    std::fprintf(stderr, "usage: sample_age WATERMARK(1..30) [PROFILES_XML [SECONDS]]\n");
    return 64;
  }
  if (argc > 3) g_seconds = std::clamp(std::strtod(argv[3], nullptr), 3.0, 600.0);
  measure(static_cast<int>(watermark), argc > 2 ? argv[2] : "");
  return 0;
}
