#include "dds/ros_discovery_info.hpp"

#include <algorithm>
#include <fastdds/dds/publisher/qos/DataWriterQos.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>
#include <stdexcept>

#include "ros2_msgsPubSubTypes.h"

namespace headingd::app {

using namespace eprosima::fastdds::dds;

namespace {

constexpr const char* kTypeName = "rmw_dds_common::msg::dds_::ParticipantEntitiesInfo_";

// rmw_fastrtps's GID: the 16-byte GUID (prefix, then entity id), zero-padded to the Gid size.
template <typename Gid>
Gid gid_of(const eprosima::fastrtps::rtps::GUID_t& guid) {
  Gid gid;
  gid.data().fill(0);
  std::copy(guid.guidPrefix.value, guid.guidPrefix.value + 12, gid.data().begin());
  std::copy(guid.entityId.value, guid.entityId.value + 4, gid.data().begin() + 12);
  return gid;
}

template <typename Info, typename Node, typename Gid, typename PubSubType>
DataWriter* publish(DomainParticipant& participant, Publisher& publisher, const RosSettings& ros,
                    const std::vector<const DataReader*>& readers, const std::vector<const DataWriter*>& writers) {
  TypeSupport type(new PubSubType());
  type->setName(kTypeName);  // Humble's 24-byte layout travels under the same name
  type.register_type(&participant);
  Topic* topic = participant.create_topic(kRosDiscoveryTopic, kTypeName, TOPIC_QOS_DEFAULT);
  if (topic == nullptr) throw std::runtime_error(std::string("cannot create DDS topic ") + kRosDiscoveryTopic);
  DataWriterQos qos = DATAWRITER_QOS_DEFAULT;
  qos.reliability().kind = RELIABLE_RELIABILITY_QOS;
  qos.durability().kind = TRANSIENT_LOCAL_DURABILITY_QOS;
  qos.history().kind = KEEP_LAST_HISTORY_QOS;
  qos.history().depth = 1;
  DataWriter* writer = publisher.create_datawriter(topic, qos);
  if (writer == nullptr) throw std::runtime_error(std::string("cannot create a DDS writer for ") + kRosDiscoveryTopic);
  Node node;
  node.node_namespace(ros.node_namespace);
  node.node_name(ros.node_name);
  for (const DataReader* reader : readers) node.reader_gid_seq().push_back(gid_of<Gid>(reader->guid()));
  for (const DataWriter* w : writers) node.writer_gid_seq().push_back(gid_of<Gid>(w->guid()));
  Info info;
  info.gid(gid_of<Gid>(participant.guid()));
  info.node_entities_info_seq().push_back(node);
  writer->write(&info);
  return writer;
}

}  // namespace

DataWriter* publish_ros_discovery_info(DomainParticipant& participant, Publisher& publisher, const RosSettings& ros,
                                       const std::vector<const DataReader*>& readers,
                                       const std::vector<const DataWriter*>& writers) {
  if (ros.distro == RosDistro::Humble) {
    namespace m = rmw_dds_common_humble::msg::dds_;
    return publish<m::ParticipantEntitiesInfo_, m::NodeEntitiesInfo_, m::Gid_, m::ParticipantEntitiesInfo_PubSubType>(
        participant, publisher, ros, readers, writers);
  }
  namespace m = rmw_dds_common::msg::dds_;
  return publish<m::ParticipantEntitiesInfo_, m::NodeEntitiesInfo_, m::Gid_, m::ParticipantEntitiesInfo_PubSubType>(
      participant, publisher, ros, readers, writers);
}

}  // namespace headingd::app
