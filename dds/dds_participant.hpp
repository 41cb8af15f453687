#pragma once
// Creating and deleting a Fast DDS participant the way every headingd tool needs it: XML
// profiles loaded first (when configured), the Discovery Server client set up (when
// configured), everything deleted on the way out.
#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/DomainParticipantListener.hpp>
#include <fastdds/dds/publisher/qos/DataWriterQos.hpp>
#include <fastdds/dds/subscriber/qos/DataReaderQos.hpp>
#include <string>

#include "dds/dds_settings.hpp"

namespace headingd::app {

// `listener` hears about discovery from the start; `user_data` goes to every other participant.
eprosima::fastdds::dds::DomainParticipant* create_participant(
    const DdsSettings& settings, const std::string& name,
    eprosima::fastdds::dds::DomainParticipantListener* listener = nullptr, const std::string& user_data = {});
void delete_participant(eprosima::fastdds::dds::DomainParticipant* participant);
// Data sharing (a reader mapping the writer's /dev/shm segment) follows the transport: off
// unless shared memory was chosen, for the same reason (segments only their owner can map).
void apply_transport(const DdsSettings& settings, eprosima::fastdds::dds::DataWriterQos& qos);
void apply_transport(const DdsSettings& settings, eprosima::fastdds::dds::DataReaderQos& qos);
// Wall-clock time now, s (the epoch of message stamps).
double wall_now_s();

}  // namespace headingd::app
