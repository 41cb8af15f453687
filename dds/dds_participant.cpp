#include "dds/dds_participant.hpp"

#include <fastdds/rtps/attributes/ServerAttributes.h>
#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>
#include <fastrtps/utils/IPLocator.h>

#include <cstdlib>
#include <ctime>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/domain/qos/DomainParticipantQos.hpp>
#include <fastdds/dds/log/Log.hpp>
#include <memory>
#include <stdexcept>
#include <vector>

#include "dds/server_address.hpp"

namespace headingd::app {

using namespace eprosima::fastdds::dds;
using eprosima::fastdds::rtps::get_server_client_default_guidPrefix;
using eprosima::fastdds::rtps::UDPv4TransportDescriptor;
using eprosima::fastrtps::rtps::DiscoveryProtocol_t;
using eprosima::fastrtps::rtps::IPLocator;
using eprosima::fastrtps::rtps::Locator_t;
using eprosima::fastrtps::rtps::RemoteServerAttributes;

double wall_now_s() {
  timespec ts{};
  clock_gettime(CLOCK_REALTIME, &ts);
  return static_cast<double>(ts.tv_sec) + static_cast<double>(ts.tv_nsec) * 1e-9;
}

// A participant profile named "headingd" in the configured XML decides the transports itself.
bool from_profile_in_force(const DdsSettings& settings, DomainParticipantFactory* factory) {
  DomainParticipantQos unused;
  return settings.profiles_xml &&
         factory->get_participant_qos_from_profile("headingd", unused) == ReturnCode_t::RETCODE_OK;
}

void apply_transport(const DdsSettings& settings, DataWriterQos& qos) {
  if (settings.transport != DdsTransport::SharedMemory) qos.data_sharing().off();
}

void apply_transport(const DdsSettings& settings, DataReaderQos& qos) {
  if (settings.transport != DdsTransport::SharedMemory) qos.data_sharing().off();
}

DomainParticipant* create_participant(const DdsSettings& settings, const std::string& name,
                                      DomainParticipantListener* listener, const std::string& user_data) {
  // HEADINGD_DDS_LOG=warning|info shows Fast DDS's own diagnostics (security set-up, discovery).
  if (const char* level = std::getenv("HEADINGD_DDS_LOG")) {
    const std::string text = level;
    Log::SetVerbosity(text == "info" ? Log::Kind::Info : text == "warning" ? Log::Kind::Warning : Log::Kind::Error);
  }
  auto* factory = DomainParticipantFactory::get_instance();
  if (settings.profiles_xml && factory->load_XML_profiles_file(*settings.profiles_xml) != ReturnCode_t::RETCODE_OK) {
    throw std::runtime_error("cannot load Fast DDS XML profiles from " + *settings.profiles_xml);
  }
  DomainParticipantQos qos = factory->get_default_participant_qos();
  // A participant profile named "headingd" in the XML file, if any, is ours.
  DomainParticipantQos from_profile;
  if (settings.profiles_xml &&
      factory->get_participant_qos_from_profile("headingd", from_profile) == ReturnCode_t::RETCODE_OK)
    qos = from_profile;
  qos.name(name);
  if (!user_data.empty())
    qos.user_data().setValue(std::vector<eprosima::fastrtps::rtps::octet>(user_data.begin(), user_data.end()));
  if (!from_profile_in_force(settings, factory) && settings.transport == DdsTransport::Udp) {
    // UDP alone, on every interface (loopback included): see DdsTransport for why not SHM.
    qos.transport().use_builtin_transports = false;
    qos.transport().user_transports.push_back(std::make_shared<UDPv4TransportDescriptor>());
  }
  for (std::size_t id = 0; id < settings.discovery_servers.size(); ++id) {
    const std::string& text = settings.discovery_servers[id];
    if (text.empty()) continue;
    std::string why;
    const auto address = parse_server_address(text, why);
    if (!address) throw std::runtime_error("discovery_server '" + text + "': " + why);
    Locator_t locator;
    IPLocator::setIPv4(locator, address->ipv4);
    locator.port = address->port;
    RemoteServerAttributes server;
    // The prefix `fastdds discovery -i ID` serves under.
    if (!get_server_client_default_guidPrefix(static_cast<int>(id), server.guidPrefix))
      throw std::runtime_error("discovery_server: no server GUID prefix for id " + std::to_string(id));
    server.metatrafficUnicastLocatorList.push_back(locator);
    qos.wire_protocol().builtin.discovery_config.discoveryProtocol = DiscoveryProtocol_t::CLIENT;
    qos.wire_protocol().builtin.discovery_config.m_DiscoveryServers.push_back(server);
  }
  if (settings.security.enabled) {
    const auto& s = settings.security;
    auto& properties = qos.properties().properties();
    const auto set = [&](const std::string& property, const std::string& value) {
      properties.emplace_back(property, value);
    };
    set("dds.sec.auth.plugin", "builtin.PKI-DH");
    set("dds.sec.auth.builtin.PKI-DH.identity_ca", "file://" + s.identity_ca);
    set("dds.sec.auth.builtin.PKI-DH.identity_certificate", "file://" + s.certificate);
    set("dds.sec.auth.builtin.PKI-DH.private_key", "file://" + s.private_key);
    set("dds.sec.access.plugin", "builtin.Access-Permissions");
    set("dds.sec.access.builtin.Access-Permissions.permissions_ca", "file://" + s.permissions_ca);
    set("dds.sec.access.builtin.Access-Permissions.governance", "file://" + s.governance);
    set("dds.sec.access.builtin.Access-Permissions.permissions", "file://" + s.permissions);
    set("dds.sec.crypto.plugin", "builtin.AES-GCM-GMAC");
  }
  // Only the discovery callbacks: our readers have listeners of their own.
  auto* participant =
      factory->create_participant(static_cast<DomainId_t>(settings.domain_id), qos, listener, StatusMask::none());
  if (participant == nullptr) {
    throw std::runtime_error("cannot create a DDS participant on domain " + std::to_string(settings.domain_id) +
                             (settings.security.enabled ? " (DDS Security: check the certificates, key, governance and "
                                                          "permissions files)"
                                                        : ""));
  }
  return participant;
}

void delete_participant(DomainParticipant* participant) {
  if (participant == nullptr) return;
  participant->delete_contained_entities();
  DomainParticipantFactory::get_instance()->delete_participant(participant);
}

}  // namespace headingd::app
