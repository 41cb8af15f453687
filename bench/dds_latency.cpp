// Sample-to-subscriber latency over DDS at 400 Hz, and the publisher's CPU share. A child
// process subscribes to Orientation (Fast DDS, loopback profile); the parent turns simulated
// gyro samples into estimates at 400 Hz real time and publishes each one, stamped with the wall
// clock at the moment the sample is handed to the estimator. Latency = receive time - stamp.
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
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
#include "machine.hpp"
#include "pipeline/dds_sink.hpp"
#include "pipeline/pipeline.hpp"
#include "sim/simulated_source.hpp"

using namespace headingd;
using namespace eprosima::fastdds::dds;

namespace {

constexpr double kRateHz = 400.0;
constexpr double kSeconds = 20.0;

class Latencies : public DataReaderListener {
 public:
  std::vector<double> us;
  void on_data_available(DataReader* reader) override {
    headingd::msg::Orientation m;
    SampleInfo info;
    while (reader->take_next_sample(&m, &info) == ReturnCode_t::RETCODE_OK) {
      if (!info.valid_data) continue;
      const double stamp = m.stamp().sec() + m.stamp().nanosec() * 1e-9;
      us.push_back((app::wall_now_s() - stamp) * 1e6);
    }
  }
};

int subscriber(const app::DdsSettings& settings, int out_fd) {
  auto* participant = app::create_participant(settings, "latency-subscriber");
  TypeSupport type(new headingd::msg::OrientationPubSubType());
  type.register_type(participant);
  auto* topic =
      participant->create_topic(app::topic_name(settings, "orientation"), type.get_type_name(), TOPIC_QOS_DEFAULT);
  auto* sub = participant->create_subscriber(SUBSCRIBER_QOS_DEFAULT);
  Latencies listener;
  listener.us.reserve(20000);
  DataReaderQos qos = DATAREADER_QOS_DEFAULT;
  qos.reliability().kind = BEST_EFFORT_RELIABILITY_QOS;
  app::apply_transport(settings, qos);
  sub->create_datareader(topic, qos, &listener);
  std::this_thread::sleep_for(std::chrono::duration<double>(kSeconds + 4.0));
  app::delete_participant(participant);
  const auto bytes = static_cast<ssize_t>(listener.us.size() * sizeof(double));
  return write(out_fd, listener.us.data(), static_cast<std::size_t>(bytes)) == bytes ? 0 : 1;
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

}  // namespace

int main(int argc, char** argv) {
  app::DdsSettings settings{};
  settings.domain_id = 45;
  settings.orientation_rate_hz = kRateHz;
  if (argc > 1) settings.profiles_xml = argv[1];
  int fds[2];
  if (pipe(fds) != 0) return 1;
  const pid_t child = fork();
  if (child == 0) {
    close(fds[0]);
    _exit(subscriber(settings, fds[1]));
  }
  close(fds[1]);
  std::printf("machine: %s\n", bench::machine_description().c_str());
  double cpu = 0.0, wall = 0.0;
  std::uint64_t sent = 0;
  {
    app::DdsNode node(settings);
    node.wait_for_subscribers(10.0);
    // The daemon's own pipeline, the simulator paced at 400 Hz, each message stamped "now".
    drivers::SimulatedSource source(*drivers::build_scenario("agv", 1, kSeconds / 3600.0), 1);
    pipeline::PipelineOptions options;
    options.pacer.emplace(1.0, nullptr);
    pipeline::Pipeline line(source, std::make_unique<core::Estimator>(), options);
    pipeline::DdsSink publisher(node, source, pipeline::StampClock::EachSample);
    line.add_sink(publisher);
    const auto start = std::chrono::steady_clock::now();
    const double cpu_start = cpu_s();
    line.run();
    cpu = cpu_s() - cpu_start;
    wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    sent = node.orientation_sent();
  }
  std::vector<double> us;
  double buffer[4096];
  ssize_t n;
  while ((n = read(fds[0], buffer, sizeof buffer)) > 0)
    us.insert(us.end(), buffer, buffer + n / static_cast<ssize_t>(sizeof(double)));
  waitpid(child, nullptr, 0);
  if (us.empty()) {
    std::printf("no messages received\n");
    return 1;
  }
  std::printf("%zu of %llu Orientation messages received at %.0f Hz over %.0f s\n", us.size(),
              static_cast<unsigned long long>(sent), kRateHz, wall);
  std::printf("sample-to-subscriber latency: p50 %.0f us, p99 %.0f us, max %.0f us\n", percentile(us, 0.5),
              percentile(us, 0.99), percentile(us, 1.0));
  std::printf("publisher process (simulator + estimator + DDS at 400 Hz): %.2f %% of one core\n", 100.0 * cpu / wall);
  return 0;
}
