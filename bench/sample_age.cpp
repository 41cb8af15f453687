// Sample age at the subscriber: from the chip's sampling instant (as the driver reconstructs it
// from the watermark edge; the stamps the daemon publishes) to the moment a subscriber in another
// process receives the Orientation message, over Fast DDS on loopback, for FIFO watermarks 1, 2,
// 4, 8 and 16 at 400 Hz. The chip is the register-level simulator in real time: real FIFO
// timing and the I2C transfer time of every burst (bytes x 9 bits / 400 kHz). Also the
// publishing process's CPU share (simulator included, so an upper bound).
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

constexpr double kSeconds = 15.0;

class Ages : public DataReaderListener {
 public:
  std::vector<double> ms;
  void on_data_available(DataReader* reader) override {
    headingd::msg::Orientation m;
    SampleInfo info;
    while (reader->take_next_sample(&m, &info) == ReturnCode_t::RETCODE_OK) {
      if (!info.valid_data) continue;
      const double stamp = m.stamp().sec() + m.stamp().nanosec() * 1e-9;
      ms.push_back((app::wall_now_s() - stamp) * 1e3);
    }
  }
};

int subscriber(const app::DdsSettings& settings, int out_fd) {
  auto* participant = app::create_participant(settings, "age-subscriber");
  TypeSupport type(new headingd::msg::OrientationPubSubType());
  type.register_type(participant);
  auto* topic =
      participant->create_topic(app::topic_name(settings, "orientation"), type.get_type_name(), TOPIC_QOS_DEFAULT);
  auto* sub = participant->create_subscriber(SUBSCRIBER_QOS_DEFAULT);
  Ages listener;
  listener.ms.reserve(4096);
  DataReaderQos qos = DATAREADER_QOS_DEFAULT;
  qos.reliability().kind = BEST_EFFORT_RELIABILITY_QOS;
  app::apply_transport(settings, qos);
  sub->create_datareader(topic, qos, &listener);
  std::this_thread::sleep_for(std::chrono::duration<double>(kSeconds + 6.0));
  app::delete_participant(participant);
  const auto bytes = static_cast<ssize_t>(listener.ms.size() * sizeof(double));
  return write(out_fd, listener.ms.data(), static_cast<std::size_t>(bytes)) == bytes ? 0 : 1;
}

double cpu_s() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
         static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec) * 1e-6;
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
  double cpu = 0.0, wall = 0.0;
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
    options.duration_s = kSeconds;
    pipeline::Pipeline line(driver, std::make_unique<core::Estimator>(), options);
    pipeline::DdsSink publisher(node, driver, pipeline::StampClock::FirstSample);  // as the daemon, live
    line.add_sink(publisher);
    const auto start = std::chrono::steady_clock::now();
    const double cpu_start = cpu_s();
    line.run();
    cpu = cpu_s() - cpu_start;
    wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  std::vector<double> ms;
  double buffer[4096];
  ssize_t n;
  while ((n = read(fds[0], buffer, sizeof buffer)) > 0)
    ms.insert(ms.end(), buffer, buffer + n / static_cast<ssize_t>(sizeof(double)));
  close(fds[0]);
  waitpid(child, nullptr, 0);
  // The first second settles the stamps' offset (WallStamps takes the least delay over 0.5 s).
  const std::size_t skip = std::min<std::size_t>(ms.size(), static_cast<std::size_t>(settings.orientation_rate_hz));
  ms.erase(ms.begin(), ms.begin() + static_cast<long>(skip));
  if (ms.empty()) {
    std::printf("watermark %2d: no messages received\n", watermark);
    return;
  }
  std::printf(
      "watermark %2d: %zu messages, sample age p50 %.1f ms, p99 %.1f ms, max %.1f ms; publisher %.2f %% of one "
      "core\n",
      watermark, ms.size(), percentile(ms, 0.5), percentile(ms, 0.99), percentile(ms, 1.0), 100.0 * cpu / wall);
  std::fflush(stdout);
}

}  // namespace

// One watermark per process: Fast DDS does not survive a fork after a participant existed, so
// bench/sample_age.sh runs this once per watermark.
int main(int argc, char** argv) {
  char* end = nullptr;
  const long watermark = argc > 1 ? std::strtol(argv[1], &end, 10) : 16;
  if (watermark < 1 || watermark > 30 || (argc > 1 && *end != '\0')) {
    std::fprintf(stderr, "usage: sample_age WATERMARK(1..30) [PROFILES_XML]\n");
    return 64;
  }
  measure(static_cast<int>(watermark), argc > 2 ? argv[2] : "");
  return 0;
}
