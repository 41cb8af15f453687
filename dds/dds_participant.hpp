#pragma once
// Creating and deleting a Fast DDS participant the way every headingd tool needs it: XML
// profiles loaded first (when configured), the Discovery Server client set up (when
// configured), everything deleted on the way out.
#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <string>

#include "dds/dds_settings.hpp"

namespace headingd::app {

eprosima::fastdds::dds::DomainParticipant* create_participant(const DdsSettings& settings, const std::string& name);
void delete_participant(eprosima::fastdds::dds::DomainParticipant* participant);
// Wall-clock time now, s (the epoch of message stamps).
double wall_now_s();

}  // namespace headingd::app
