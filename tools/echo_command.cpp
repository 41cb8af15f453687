#include "tools/echo_command.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/publisher/qos/DataWriterQos.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/subscriber/qos/DataReaderQos.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>
#include <mutex>
#include <thread>

#include "core/units.hpp"
#include "dds/dds_participant.hpp"
#include "dds/message_format.hpp"
#include "headingdPubSubTypes.h"
#include "ros2_msgsPubSubTypes.h"
#include "service/config_file.hpp"
#include "service/exit_codes.hpp"
#include "service/signals.hpp"
#include "service/standard_output.hpp"

namespace headingd::app {

using namespace eprosima::fastdds::dds;

namespace {

std::mutex g_print;

std::atomic<std::uint64_t> g_received{0};
std::uint64_t g_limit = 0;  // --count: no line beyond it, however many readers deliver at once

template <typename Message>
class Printer : public DataReaderListener {
 public:
  explicit Printer(bool json) : json_(json) {}
  void on_data_available(DataReader* reader) override {
    Message m;
    SampleInfo info;
    while (reader->take_next_sample(&m, &info) == ReturnCode_t::RETCODE_OK) {
      if (!info.valid_data) continue;
      const std::string line = line_for(m, json_);
      std::lock_guard lock(g_print);
      if (g_limit > 0 && g_received.load() >= g_limit) return;
      std::printf("%s\n", line.c_str());
      std::fflush(stdout);
      ++g_received;
    }
  }

 private:
  bool json_;
};

// The [dds] section of the config file (defaults without one), or nothing after saying what
// is wrong with the file.
std::optional<DdsSettings> load_dds_or_report(const std::optional<std::string>& path) {
  try {
    return path ? load_config(*path).dds : DdsSettings{};
  } catch (const ConfigError& error) {
    std::fprintf(stderr, "headingd: %s\n", error.what());
    return std::nullopt;
  }
}

}  // namespace

int run_echo(const EchoOptions& options) {
  const auto loaded = load_dds_or_report(options.config_path);
  if (!loaded) return kExitConfig;
  const DdsSettings& settings = *loaded;
  std::vector<std::string> topics = options.topics;
  if (topics.empty()) topics = {"orientation", "imu", "bias", "status"};
  for (const auto& t : topics) {
    if (t != "orientation" && t != "imu" && t != "bias" && t != "status" && t != "command") {
      std::fprintf(stderr, "headingd: echo: unknown topic '%s' (known: orientation, imu, bias, status, command)\n",
                   t.c_str());
      return kExitUsage;
    }
  }
  install_stop_signals();
  g_limit = options.count;
  DomainParticipant* participant = nullptr;
  std::vector<std::unique_ptr<DataReaderListener>> listeners;
  try {
    participant = create_participant(settings, "headingd-echo");
    Subscriber* subscriber = participant->create_subscriber(SUBSCRIBER_QOS_DEFAULT);
    auto add = [&](const std::string& name, const TypeSupport& type, DataReaderListener* listener, bool latched,
                   bool reliable) {
      type.register_type(participant);
      Topic* topic = participant->create_topic(name, type.get_type_name(), TOPIC_QOS_DEFAULT);
      DataReaderQos qos = DATAREADER_QOS_DEFAULT;
      qos.reliability().kind = (latched || reliable) ? RELIABLE_RELIABILITY_QOS : BEST_EFFORT_RELIABILITY_QOS;
      qos.durability().kind = latched ? TRANSIENT_LOCAL_DURABILITY_QOS : VOLATILE_DURABILITY_QOS;
      qos.history().kind = KEEP_LAST_HISTORY_QOS;
      qos.history().depth = latched ? 1 : 100;
      apply_transport(settings, qos);
      if (topic == nullptr || subscriber->create_datareader(topic, qos, listener) == nullptr)
        throw std::runtime_error("cannot subscribe to " + name);
    };
    for (const auto& t : topics) {
      if (t == "orientation") {
        listeners.push_back(std::make_unique<Printer<headingd::msg::Orientation>>(options.json));
        add(topic_name(settings, "orientation"), TypeSupport(new headingd::msg::OrientationPubSubType()),
            listeners.back().get(), false, options.reliable);
      } else if (t == "imu") {
        listeners.push_back(std::make_unique<Printer<sensor_msgs::msg::dds_::Imu_>>(options.json));
        add(ros_topic(settings.ros, settings.imu_topic), TypeSupport(new sensor_msgs::msg::dds_::Imu_PubSubType()),
            listeners.back().get(), false, options.reliable);
      } else if (t == "bias") {
        listeners.push_back(std::make_unique<Printer<headingd::msg::GyroBias>>(options.json));
        add(topic_name(settings, "bias"), TypeSupport(new headingd::msg::GyroBiasPubSubType()), listeners.back().get(),
            true, true);
      } else if (t == "status") {
        listeners.push_back(std::make_unique<Printer<headingd::msg::Status>>(options.json));
        add(topic_name(settings, "status"), TypeSupport(new headingd::msg::StatusPubSubType()), listeners.back().get(),
            true, true);
      } else {
        listeners.push_back(std::make_unique<Printer<headingd::msg::HeadingCommand>>(options.json));
        add(topic_name(settings, "command"), TypeSupport(new headingd::msg::HeadingCommandPubSubType()),
            listeners.back().get(), false, true);
      }
    }
  } catch (const std::exception& error) {
    std::fprintf(stderr, "headingd: echo: %s\n", error.what());
    delete_participant(participant);
    return kExitSoftware;
  }
  const auto start = std::chrono::steady_clock::now();
  while (!stop_requested()) {
    if (options.count > 0 && g_received.load() >= options.count) break;
    if (options.timeout_s > 0 &&
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() >= options.timeout_s)
      break;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  delete_participant(participant);  // stops the listeners before they go away
  listeners.clear();
  const int code = finish_standard_output();
  // A script waiting for N messages (a health check) must see that they did not come.
  const std::uint64_t received = g_received.load();
  if (code == kExitOk && options.count > 0 && received < options.count && !stop_requested()) {
    std::fprintf(stderr, "headingd: echo: %llu of %llu messages within %g s\n",
                 static_cast<unsigned long long>(received), static_cast<unsigned long long>(options.count),
                 options.timeout_s);
    return kExitUnavailable;
  }
  return code;
}

int run_command(const CommandOptions& options) {
  const auto loaded = load_dds_or_report(options.config_path);
  if (!loaded) return kExitConfig;
  const DdsSettings& settings = *loaded;
  headingd::msg::HeadingCommand command;
  if (options.kind == "set-heading")
    command.kind(headingd::msg::CommandKind::COMMAND_SET_HEADING);
  else if (options.kind == "stopped")
    command.kind(headingd::msg::CommandKind::COMMAND_PLATFORM_STOPPED);
  else if (options.kind == "moving")
    command.kind(headingd::msg::CommandKind::COMMAND_PLATFORM_MOVING);
  else if (options.kind == "clear")
    command.kind(headingd::msg::CommandKind::COMMAND_CLEAR_HINT);
  else {
    std::fprintf(stderr, "headingd: command: '%s' is not set-heading, stopped, moving or clear\n",
                 options.kind.c_str());
    return kExitUsage;
  }
  command.heading_rad(options.heading_rad.value_or(core::deg_to_rad(options.heading_deg)));
  command.heading_variance_rad2(options.variance_deg2 * core::kRadPerDeg * core::kRadPerDeg);
  DomainParticipant* participant = nullptr;
  try {
    participant = create_participant(settings, "headingd-command");
    TypeSupport type(new headingd::msg::HeadingCommandPubSubType());
    type.register_type(participant);
    Topic* topic = participant->create_topic(topic_name(settings, "command"), type.get_type_name(), TOPIC_QOS_DEFAULT);
    Publisher* publisher = participant->create_publisher(PUBLISHER_QOS_DEFAULT);
    DataWriterQos qos = DATAWRITER_QOS_DEFAULT;
    qos.reliability().kind = RELIABLE_RELIABILITY_QOS;
    apply_transport(settings, qos);
    DataWriter* writer = publisher->create_datawriter(topic, qos);
    if (writer == nullptr) throw std::runtime_error("cannot create the HeadingCommand writer");
    // Wait for the daemon's reader, so the one message is not sent into the void.
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(options.wait_s);
    PublicationMatchedStatus matched;
    while (std::chrono::steady_clock::now() < deadline) {
      writer->get_publication_matched_status(matched);
      if (matched.current_count > 0) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    if (matched.current_count == 0)
      throw std::runtime_error("no headingd is listening on " + topic_name(settings, "command"));
    const double stamp = wall_now_s() + options.stamp_offset_s;
    command.stamp().sec(static_cast<std::int32_t>(std::floor(stamp)));
    command.stamp().nanosec(static_cast<std::uint32_t>((stamp - std::floor(stamp)) * 1e9));
    writer->write(&command);
    writer->wait_for_acknowledgments(eprosima::fastrtps::Duration_t(2, 0));
  } catch (const std::exception& error) {
    std::fprintf(stderr, "headingd: command: %s\n", error.what());
    delete_participant(participant);
    return kExitSoftware;
  }
  delete_participant(participant);
  return kExitOk;
}

}  // namespace headingd::app
