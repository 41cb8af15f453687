#include "dds/dds_node.hpp"

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/DataWriterListener.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/publisher/qos/DataWriterQos.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/subscriber/qos/DataReaderQos.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>
#include <thread>
#include <utility>

#include "core/units.hpp"
#include "core/version.hpp"
#include "dds/dds_participant.hpp"
#include "dds/imu_message.hpp"
#include "dds/ros_discovery_info.hpp"
#include "dds/shm_cleanup.hpp"
#include "dds/stop_hint.hpp"
#include "dds/wire_method.hpp"
#include "headingdPubSubTypes.h"
#include "ros2_msgsPubSubTypes.h"

namespace headingd::app {

using namespace eprosima::fastdds::dds;

namespace {

template <typename Stamp>
void set_stamp(Stamp& stamp, double t_s) {
  const double whole = std::floor(t_s);
  stamp.sec(static_cast<std::int32_t>(whole));
  stamp.nanosec(static_cast<std::uint32_t>(std::min(999999999.0, std::round((t_s - whole) * 1e9))));
}

}  // namespace

namespace {

// Our start time in the participant's user data, so two instances agree on which came first.
std::string start_mark(double started_unix_s) {
  char text[64];
  std::snprintf(text, sizeof text, "headingd started_ns=%.0f", started_unix_s * 1e9);
  return text;
}

std::optional<double> started_of(const std::vector<eprosima::fastrtps::rtps::octet>& user_data) {
  const std::string text(user_data.begin(), user_data.end());
  const std::string key = "headingd started_ns=";
  if (text.rfind(key, 0) != 0) return std::nullopt;
  char* end = nullptr;
  const double ns = std::strtod(text.c_str() + key.size(), &end);
  if (end == text.c_str() + key.size()) return std::nullopt;
  return ns / 1e9;
}

std::string prefix_text(const eprosima::fastrtps::rtps::GuidPrefix_t& prefix) {
  std::ostringstream out;
  out << prefix;
  return out.str();
}

}  // namespace

// Watches discovery for another writer on our orientation topic.
struct Discovery : public DomainParticipantListener {
  std::string orientation_topic;
  double started_unix_s = 0.0;
  std::mutex mutex;
  struct Peer {
    std::string name;
    std::optional<double> started_unix_s;
  };
  std::map<std::string, Peer> peers;  // by GUID prefix
  std::set<std::string> rivals_known;
  std::vector<Rival> rivals_new;

  void on_participant_discovery(DomainParticipant* /*participant*/,
                                eprosima::fastrtps::rtps::ParticipantDiscoveryInfo&& info) override {
    if (info.status != eprosima::fastrtps::rtps::ParticipantDiscoveryInfo::DISCOVERED_PARTICIPANT) return;
    std::lock_guard lock(mutex);
    peers[prefix_text(info.info.m_guid.guidPrefix)] = {info.info.m_participantName.to_string(),
                                                       started_of(info.info.m_userData.data_vec())};
  }

  void on_publisher_discovery(DomainParticipant* participant,
                              eprosima::fastrtps::rtps::WriterDiscoveryInfo&& info) override {
    if (info.status != eprosima::fastrtps::rtps::WriterDiscoveryInfo::DISCOVERED_WRITER) return;
    if (info.info.topicName().to_string() != orientation_topic) return;
    const auto& prefix = info.info.guid().guidPrefix;
    if (prefix == participant->guid().guidPrefix) return;  // our own writer
    std::lock_guard lock(mutex);
    const std::string key = prefix_text(prefix);
    if (!rivals_known.insert(key).second) return;
    Rival rival{key, "?", false};
    if (const auto peer = peers.find(key); peer != peers.end()) {
      rival.participant = peer->second.name;
      // The one that came later gives way; a publisher that does not say counts as earlier.
      rival.started_before_us =
          !peer->second.started_unix_s || *peer->second.started_unix_s < started_unix_s ||
          (*peer->second.started_unix_s == started_unix_s && key < prefix_text(participant->guid().guidPrefix));
    } else {
      rival.started_before_us = true;
    }
    rivals_new.push_back(rival);
  }
};

// Why inbound messages were refused, for the pipeline to log (rate-limited, at the configured
// level): the DDS layer writes no log lines of its own. Bounded: a flood is counted, not kept.
struct Refusals {
  static constexpr std::size_t kKept = 32;
  std::mutex mutex;
  std::vector<Refusal> pending;
  std::uint64_t dropped = 0;
  void add(RefusalKind kind, std::string why) {
    std::lock_guard lock(mutex);
    if (pending.size() < kKept)
      pending.push_back({kind, std::move(why)});
    else
      ++dropped;
  }
};

// The vehicle's motion (Odometry, Twist or TwistStamped) into the stop-hint tracker.
struct MotionListener : public DataReaderListener {
  StopHintType type = StopHintType::Odometry;
  std::mutex* mutex = nullptr;
  StopHintTracker* tracker = nullptr;
  Refusals* refusals = nullptr;

  template <typename Message, typename TwistOf>
  void take_all(DataReader* reader, bool stamped, TwistOf twist_of) {
    Message message;
    SampleInfo info;
    while (reader->take_next_sample(&message, &info) == ReturnCode_t::RETCODE_OK) {
      if (!info.valid_data) continue;
      MotionReport r;
      if constexpr (requires { message.header(); })
        if (stamped) r.stamp_s = message.header().stamp().sec() + message.header().stamp().nanosec() * 1e-9;
      const auto& t = twist_of(message);
      r.linear_m_s = core::Vec3(t.linear().x(), t.linear().y(), t.linear().z());
      r.angular_rad_s = core::Vec3(t.angular().x(), t.angular().y(), t.angular().z());
      std::string why;
      bool ok = false;
      {
        std::lock_guard lock(*mutex);
        ok = tracker->offer(r, wall_now_s(), why);
      }
      if (!ok) refusals->add(RefusalKind::Motion, why);
    }
  }

  void on_data_available(DataReader* reader) override {
    switch (type) {
      case StopHintType::Odometry:
        take_all<nav_msgs::msg::dds_::Odometry_>(
            reader, true, [](const auto& m) -> const auto& { return m.twist().twist(); });
        break;
      case StopHintType::Twist:
        take_all<geometry_msgs::msg::dds_::Twist_>(
            reader, false, [](const auto& m) -> const auto& { return m; });
        break;
      case StopHintType::TwistStamped:
        take_all<geometry_msgs::msg::dds_::TwistStamped_>(
            reader, true, [](const auto& m) -> const auto& { return m.twist(); });
        break;
    }
  }
};

// How many readers a writer is matched with: a volatile message that nobody reads is not built
// at all (Fast DDS would serialize it, file it in the writer's history and send it nowhere).
// A reader that matches later gets the next one, as volatile durability promises. A writer that
// an XML profile made durable keeps everything it is given, for late joiners.
struct MatchedReaders : public DataWriterListener {
  std::atomic<int> count{0};
  bool durable = false;
  void on_publication_matched(DataWriter*, const PublicationMatchedStatus& status) override {
    count.store(status.current_count, std::memory_order_relaxed);
  }
  bool any() const { return durable || count.load(std::memory_order_relaxed) > 0; }
};

struct DdsNode::Impl : public DataReaderListener {
  Discovery discovery;
  DomainParticipant* participant = nullptr;
  Publisher* publisher = nullptr;
  Subscriber* subscriber = nullptr;
  MatchedReaders orientation_readers;
  MatchedReaders imu_readers;
  DataWriter* orientation = nullptr;
  DataWriter* imu = nullptr;
  DataWriter* bias = nullptr;
  DataWriter* status = nullptr;
  DataReader* command = nullptr;
  DataWriter* diagnostics = nullptr;
  DataWriter* temperature = nullptr;
  DataWriter* discovery_info = nullptr;
  DataReader* motion = nullptr;
  CommandLimits limits;
  std::mutex mutex;
  std::vector<ValidCommand> commands;
  std::uint64_t accepted = 0, rejected = 0;
  Refusals refusals;
  MotionListener motion_listener;
  std::optional<StopHintTracker> stop_hint;  // guarded by `mutex`
  core::MotionHint hint_sent = core::MotionHint::None;

  Topic* topic(const std::string& name, const TypeSupport& type) {
    type.register_type(participant);
    auto* t = participant->create_topic(name, type.get_type_name(), TOPIC_QOS_DEFAULT);
    if (t == nullptr) throw std::runtime_error("cannot create DDS topic " + name);
    return t;
  }

  DataWriter* writer(Topic* t, DataWriterQos qos, const std::string& profile, MatchedReaders* readers = nullptr) {
    DataWriterQos from_profile;
    if (publisher->get_datawriter_qos_from_profile(profile, from_profile) == ReturnCode_t::RETCODE_OK)
      qos = from_profile;
    if (readers != nullptr) readers->durable = qos.durability().kind != VOLATILE_DURABILITY_QOS;
    auto* w = readers == nullptr ? publisher->create_datawriter(t, qos)
                                 : publisher->create_datawriter(t, qos, readers, StatusMask::publication_matched());
    if (w == nullptr) throw std::runtime_error("cannot create a DDS writer for " + t->get_name());
    return w;
  }

  void on_data_available(DataReader* reader) override {
    headingd::msg::HeadingCommand message;
    SampleInfo info;
    while (reader->take_next_sample(&message, &info) == ReturnCode_t::RETCODE_OK) {
      if (!info.valid_data) continue;
      CommandIn in{message.stamp().sec(), message.stamp().nanosec(), static_cast<std::int32_t>(message.kind()),
                   message.heading_rad(), message.heading_variance_rad2()};
      std::string why;
      const auto valid = validate_command(in, wall_now_s(), limits, why);
      {
        std::lock_guard lock(mutex);
        if (valid) {
          ++accepted;
          commands.push_back(*valid);
        } else {
          ++rejected;
        }
      }
      if (!valid) refusals.add(RefusalKind::Command, why);
    }
  }
};

DdsNode::DdsNode(const DdsSettings& settings)
    : impl_(std::make_unique<Impl>()), settings_(settings), diagnostics_builder_(settings.ros) {
  Impl& d = *impl_;
  d.limits = settings.command_limits;
  if (settings.transport == DdsTransport::SharedMemory) {
    // What a killed headingd (or any process of ours) left in /dev/shm goes before we add ours.
    if (const std::size_t removed = remove_stale_fastdds_files("/dev/shm"))
      std::fprintf(stderr, "<5>headingd: removed %zu shared-memory files of Fast DDS processes that are gone\n",
                   removed);
  }
  try {
    d.discovery.orientation_topic = topic_name(settings, "orientation");
    d.discovery.started_unix_s = wall_now_s();
    d.participant = create_participant(settings, "headingd", &d.discovery, start_mark(d.discovery.started_unix_s));
    d.publisher = d.participant->create_publisher(PUBLISHER_QOS_DEFAULT);
    d.subscriber = d.participant->create_subscriber(SUBSCRIBER_QOS_DEFAULT);
    if (d.publisher == nullptr || d.subscriber == nullptr)
      throw std::runtime_error("cannot create DDS publisher/subscriber");

    DataWriterQos stream = DATAWRITER_QOS_DEFAULT;  // orientation and Imu
    stream.reliability().kind = settings.orientation_reliable ? RELIABLE_RELIABILITY_QOS : BEST_EFFORT_RELIABILITY_QOS;
    stream.durability().kind = VOLATILE_DURABILITY_QOS;
    stream.history().kind = KEEP_LAST_HISTORY_QOS;
    // Best effort keeps the newest kOrientationBurst: one FIFO wake-up can make several
    // messages due back to back (a 400 Hz chip waking at 24 Hz, published at 50 Hz: 2-3), and
    // a history of one dropped the first of each pair. A reader that falls further behind
    // loses the oldest, never the newest; reliable keeps 100 and blocks at most 100 ms.
    stream.history().depth = settings.orientation_reliable ? 100 : kOrientationBurst;
    // Promised only when configured: Fast DDS restarts the deadline timer on every write, waking
    // its event thread once per message (a quarter of the publisher's CPU at 50 Hz, bench/sample_age).
    // A reader requesting a deadline matches only a writer offering one at least as short.
    if (settings.orientation_deadline_periods > 0.0)
      stream.deadline().period =
          eprosima::fastrtps::Duration_t(settings.orientation_deadline_periods / settings.orientation_rate_hz);

    apply_transport(settings, stream);

    DataWriterQos latched = DATAWRITER_QOS_DEFAULT;  // bias and status: the latest for late joiners
    latched.reliability().kind = RELIABLE_RELIABILITY_QOS;
    latched.durability().kind = TRANSIENT_LOCAL_DURABILITY_QOS;
    latched.history().kind = KEEP_LAST_HISTORY_QOS;
    latched.history().depth = 1;
    apply_transport(settings, latched);

    d.orientation =
        d.writer(d.topic(topic_name(settings, "orientation"), TypeSupport(new headingd::msg::OrientationPubSubType())),
                 stream, "headingd_orientation", &d.orientation_readers);
    const RosSettings& ros = settings.ros;
    if (settings.publish_imu) {
      d.imu = d.writer(
          d.topic(ros_topic(ros, settings.imu_topic), TypeSupport(new sensor_msgs::msg::dds_::Imu_PubSubType())),
          stream, "headingd_imu", &d.imu_readers);
    }
    // ROS's default profile (reliable, volatile, keep last 10): what diagnostic_updater and
    // most drivers publish with, and matched by reliable and best-effort readers alike.
    DataWriterQos ros_default = DATAWRITER_QOS_DEFAULT;
    ros_default.reliability().kind = RELIABLE_RELIABILITY_QOS;
    ros_default.durability().kind = VOLATILE_DURABILITY_QOS;
    ros_default.history().kind = KEEP_LAST_HISTORY_QOS;
    ros_default.history().depth = 10;
    apply_transport(settings, ros_default);
    if (ros.diagnostics) {
      d.diagnostics = d.writer(d.topic(ros_topic(ros, "/diagnostics"),
                                       TypeSupport(new diagnostic_msgs::msg::dds_::DiagnosticArray_PubSubType())),
                               ros_default, "headingd_diagnostics");
    }
    if (!ros.temperature_topic.empty()) {
      d.temperature = d.writer(d.topic(ros_topic(ros, ros.temperature_topic),
                                       TypeSupport(new sensor_msgs::msg::dds_::Temperature_PubSubType())),
                               ros_default, "headingd_temperature");
    }
    d.bias = d.writer(d.topic(topic_name(settings, "bias"), TypeSupport(new headingd::msg::GyroBiasPubSubType())),
                      latched, "headingd_bias");
    d.status = d.writer(d.topic(topic_name(settings, "status"), TypeSupport(new headingd::msg::StatusPubSubType())),
                        latched, "headingd_status");
    DataReaderQos command_qos = DATAREADER_QOS_DEFAULT;
    command_qos.reliability().kind = RELIABLE_RELIABILITY_QOS;
    command_qos.history().kind = KEEP_LAST_HISTORY_QOS;
    command_qos.history().depth = 16;
    apply_transport(settings, command_qos);
    d.command = d.subscriber->create_datareader(
        d.topic(topic_name(settings, "command"), TypeSupport(new headingd::msg::HeadingCommandPubSubType())),
        command_qos, &d);
    if (d.command == nullptr) throw std::runtime_error("cannot create the HeadingCommand reader");
    if (!ros.stop_hint.topic.empty()) {
      d.stop_hint.emplace(ros.stop_hint, settings.command_limits);
      d.motion_listener.type = ros.stop_hint.type;
      d.motion_listener.mutex = &d.mutex;
      d.motion_listener.tracker = &*d.stop_hint;
      d.motion_listener.refusals = &d.refusals;
      TypeSupport type(new nav_msgs::msg::dds_::Odometry_PubSubType());
      if (ros.stop_hint.type == StopHintType::Twist)
        type = TypeSupport(new geometry_msgs::msg::dds_::Twist_PubSubType());
      if (ros.stop_hint.type == StopHintType::TwistStamped)
        type = TypeSupport(new geometry_msgs::msg::dds_::TwistStamped_PubSubType());
      // Best effort matches a vehicle's best-effort and reliable writers alike.
      DataReaderQos motion_qos = DATAREADER_QOS_DEFAULT;
      motion_qos.reliability().kind = BEST_EFFORT_RELIABILITY_QOS;
      motion_qos.durability().kind = VOLATILE_DURABILITY_QOS;
      motion_qos.history().kind = KEEP_LAST_HISTORY_QOS;
      motion_qos.history().depth = 10;
      apply_transport(settings, motion_qos);
      d.motion = d.subscriber->create_datareader(d.topic(ros_topic(ros, ros.stop_hint.topic), type), motion_qos,
                                                 &d.motion_listener);
      if (d.motion == nullptr) throw std::runtime_error("cannot create the reader for " + ros.stop_hint.topic);
    }
    if (ros.discovery_info) {
      std::vector<const DataReader*> readers{d.command};
      if (d.motion != nullptr) readers.push_back(d.motion);
      std::vector<const DataWriter*> writers;
      for (const DataWriter* w : {d.orientation, d.imu, d.bias, d.status, d.diagnostics, d.temperature})
        if (w != nullptr) writers.push_back(w);
      d.discovery_info = publish_ros_discovery_info(*d.participant, *d.publisher, ros, readers, writers);
    }
  } catch (...) {
    delete_participant(d.participant);
    throw;
  }
}

DdsNode::~DdsNode() { delete_participant(impl_->participant); }

bool DdsNode::wait_for_subscribers(double seconds, const std::atomic<bool>* stop) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  PublicationMatchedStatus matched;
  while (true) {
    impl_->orientation->get_publication_matched_status(matched);
    if (matched.current_count > 0) {
      // The writer knows the reader; give the reader a moment to know the writer too, or the
      // first messages may arrive before the reader accepts them.
      std::this_thread::sleep_for(std::chrono::milliseconds(300));
      return true;
    }
    if (std::chrono::steady_clock::now() >= deadline || (stop != nullptr && stop->load())) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
}

void DdsNode::take_commands(std::vector<ValidCommand>& out) {
  Impl& d = *impl_;
  std::lock_guard lock(d.mutex);
  out.insert(out.end(), d.commands.begin(), d.commands.end());
  d.commands.clear();
  if (d.stop_hint) {
    // The vehicle's motion, as a hint command whenever what it says changes (stale = none).
    const core::MotionHint hint = d.stop_hint->hint(wall_now_s());
    if (hint != d.hint_sent) {
      d.hint_sent = hint;
      const CommandKind kind = hint == core::MotionHint::Stopped  ? CommandKind::PlatformStopped
                               : hint == core::MotionHint::Moving ? CommandKind::PlatformMoving
                                                                  : CommandKind::ClearHint;
      out.push_back(ValidCommand{.kind = kind, .hint = hint});
    }
  }
}

std::uint64_t DdsNode::take_refusals(std::vector<Refusal>& out) {
  std::lock_guard lock(impl_->refusals.mutex);
  out.insert(out.end(), impl_->refusals.pending.begin(), impl_->refusals.pending.end());
  impl_->refusals.pending.clear();
  return std::exchange(impl_->refusals.dropped, 0);
}

InboundCounts DdsNode::inbound() const {
  std::lock_guard lock(impl_->mutex);
  InboundCounts c{.commands_accepted = impl_->accepted, .commands_rejected = impl_->rejected};
  if (impl_->stop_hint) {
    c.motion_accepted = impl_->stop_hint->accepted();
    c.motion_refused = impl_->stop_hint->refused();
  }
  return c;
}

std::vector<Rival> DdsNode::take_rivals() {
  std::lock_guard lock(impl_->discovery.mutex);
  std::vector<Rival> out;
  out.swap(impl_->discovery.rivals_new);
  return out;
}

std::uint64_t DdsNode::commands_accepted() const { return inbound().commands_accepted; }
std::uint64_t DdsNode::commands_rejected() const { return inbound().commands_rejected; }

bool DdsNode::due(const core::Estimate& e) {
  if (e.closed.closed) last_verdict_still_ = e.closed.accepted;
  rates_.add(e.rate_dps);
  const double t = e.t_s;
  return t >= next_orientation_s_ || (t >= next_bias_s_ && !e.in_startup) || t >= next_status_s_;
}

void DdsNode::publish(const core::Estimate& e, const core::Diagnostics& diagnostics, const StatusReport& report,
                      double wall_offset_s) {
  Impl& d = *impl_;
  const double t = e.t_s;
  const double stamp_s = t + wall_offset_s;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  if (t >= next_orientation_s_) {
    // On the grid, which a publication up to half a period late keeps (a wake-up's newest
    // sample, pipeline/dds_sink); after a longer gap the grid starts again from this message,
    // so the gap is not followed by a burst of messages catching up.
    const double period_s = 1.0 / settings_.orientation_rate_hz;
    const bool on_grid = next_orientation_s_ > -1e299 && next_orientation_s_ + period_s >= t - 0.5 * period_s;
    next_orientation_s_ = on_grid ? next_orientation_s_ + period_s : t + period_s;
    const double heading_rad = core::deg_to_rad(e.heading_deg);
    const double sigma_rad = core::deg_to_rad(e.heading_sigma_deg);
    const core::Vec3 rate_rad = e.rate_dps * core::kRadPerDeg;
    headingd::msg::Orientation o;
    set_stamp(o.stamp(), stamp_s);
    o.seq(++orientation_seq_);
    orientation_sample_t_s_ = t;
    o.heading_rad(heading_rad);
    // NaN: the method gives none; infinite: the estimator faulted.
    o.heading_variance_rad2(std::isnan(sigma_rad) ? nan : sigma_rad * sigma_rad);
    o.qw(e.attitude.w());
    o.qx(e.attitude.x());
    o.qy(e.attitude.y());
    o.qz(e.attitude.z());
    o.rate_x_rad_s(rate_rad.x());
    o.rate_y_rad_s(rate_rad.y());
    o.rate_z_rad_s(rate_rad.z());
    o.still(e.in_startup || last_verdict_still_);
    o.heading_fixes(diagnostics.heading_fixes);
    o.yaw_offset_rad(core::deg_to_rad(diagnostics.heading_fix_offset_deg));
    if (d.orientation_readers.any()) d.orientation->write(&o);
    if (d.imu != nullptr && d.imu_readers.any()) {
      const ImuFields f = imu_fields(e, diagnostics, rates_, settings_.ros);
      sensor_msgs::msg::dds_::Imu_ imu;
      set_stamp(imu.header().stamp(), stamp_s);
      imu.header().frame_id(settings_.frame_id);
      imu.orientation().x(f.orientation_xyzw[0]);
      imu.orientation().y(f.orientation_xyzw[1]);
      imu.orientation().z(f.orientation_xyzw[2]);
      imu.orientation().w(f.orientation_xyzw[3]);
      imu.orientation_covariance() = f.orientation_covariance;
      imu.angular_velocity().x(f.angular_velocity_rad_s[0]);
      imu.angular_velocity().y(f.angular_velocity_rad_s[1]);
      imu.angular_velocity().z(f.angular_velocity_rad_s[2]);
      imu.angular_velocity_covariance() = f.angular_velocity_covariance;
      imu.linear_acceleration_covariance() = f.linear_acceleration_covariance;
      d.imu->write(&imu);
    }
    rates_.clear();
  }
  // No GyroBias before the start-up segment has measured one: a zero bias would read as known.
  if (t >= next_bias_s_ && !e.in_startup) {
    next_bias_s_ = t + 1.0;
    headingd::msg::GyroBias b;
    set_stamp(b.stamp(), stamp_s);
    const core::Vec3 bias_rad = e.bias_dps * core::kRadPerDeg;
    const core::Vec3 sigma_rad = e.bias_sigma_dps * core::kRadPerDeg;
    b.bias_x_rad_s(bias_rad.x());
    b.bias_y_rad_s(bias_rad.y());
    b.bias_z_rad_s(bias_rad.z());
    b.sigma_x_rad_s(sigma_rad.x());
    b.sigma_y_rad_s(sigma_rad.y());
    b.sigma_z_rad_s(sigma_rad.z());
    b.temperature_c(e.temp_c);
    const double last_still = diagnostics.last_still_t_s;
    set_stamp(b.last_still(), std::isfinite(last_still) ? last_still + wall_offset_s : 0.0);
    b.accepted_segments(diagnostics.accepted_segments);
    b.rejected_segments(diagnostics.rejected_segments);
    b.method(to_wire(diagnostics.method));
    d.bias->write(&b);
  }
  if (t >= next_status_s_) {
    next_status_s_ = t + 1.0;
    const InboundCounts counts = inbound();
    headingd::msg::Status s;
    set_stamp(s.stamp(), stamp_s);
    s.state(static_cast<headingd::msg::SensorState>(static_cast<int>(report.state)));
    s.sample_rate_hz(report.sample_rate_hz);
    s.samples_received(report.samples_received);
    s.samples_dropped(report.samples_dropped);
    s.bus_errors(report.bus_errors);
    s.fifo_overruns(report.fifo_overruns);
    s.commands_accepted(counts.commands_accepted);
    s.commands_rejected(counts.commands_rejected);
    s.uptime_s(report.uptime_s);
    s.version(kVersion);
    s.other_publishers(report.other_publishers);
    s.motion_messages_accepted(counts.motion_accepted);
    s.motion_messages_refused(counts.motion_refused);
    d.status->write(&s);
    publish_ros_health(e, diagnostics, report, counts, stamp_s);
  }
}

void DdsNode::publish_ros_health(const core::Estimate& e, const core::Diagnostics& diagnostics,
                                 const StatusReport& report, const InboundCounts& counts, double stamp_s) {
  Impl& d = *impl_;
  if (d.diagnostics != nullptr) {
    diagnostic_msgs::msg::dds_::DiagnosticArray_ array;
    set_stamp(array.header().stamp(), stamp_s);
    for (const DiagnosticEntry& entry : diagnostics_builder_.build(e, diagnostics, report, counts)) {
      diagnostic_msgs::msg::dds_::DiagnosticStatus_ status;
      status.level(static_cast<std::uint8_t>(entry.level));
      status.name(entry.name);
      status.message(entry.message);
      status.hardware_id(entry.hardware_id);
      for (const auto& [key, value] : entry.values) {
        diagnostic_msgs::msg::dds_::KeyValue_ kv;
        kv.key(key);
        kv.value(value);
        status.values().push_back(std::move(kv));
      }
      array.status().push_back(std::move(status));
    }
    d.diagnostics->write(&array);
  }
  // A recording without temperatures has none to give.
  if (d.temperature != nullptr && std::isfinite(e.temp_c)) {
    sensor_msgs::msg::dds_::Temperature_ temperature;
    set_stamp(temperature.header().stamp(), stamp_s);
    temperature.header().frame_id(settings_.frame_id);
    temperature.temperature(e.temp_c);
    temperature.variance(0.0);  // unknown: the L3GD20H's sensor is uncalibrated (datasheet: typ. -1 LSB/degC)
    d.temperature->write(&temperature);
  }
}

}  // namespace headingd::app
