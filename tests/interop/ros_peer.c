/* A ROS 2 peer built on Eclipse Cyclone DDS (the second DDS implementation), with the ROS 2
 * types idlc generates from idl/ros2/ros2_msgs.idl, which is written from the public message
 * definitions: it sees headingd as a ROS 2 node would, and plays the vehicle.
 *
 *   ros_peer listen DOMAIN SECONDS [NAMESPACE]
 *     Prints one line per message received on the Imu (by a ROS-default reliable reader and by a
 *     sensor-data best-effort reader), /diagnostics, the temperature, ros_discovery_info and
 *     headingd/orientation, and one line per endpoint discovered (DCPSPublication and
 *     DCPSSubscription: topic, type, reliability, durability).
 *   ros_peer odom|twist DOMAIN TOPIC MODE SECONDS
 *     Publishes nav_msgs/Odometry (or geometry_msgs/Twist) at 20 Hz. MODE: stopped (zero twist), moving (1 m/s, 0.2
 * rad/s), nan (NaN twist), stale (stamped 60 s ago), future (stamped 60 s ahead). ros_peer bad-commands DOMAIN N RATE
 *     Sends N HeadingCommands with a NaN heading at RATE per second (reliable, keep all).
 *   ros_peer set-heading DOMAIN HEADING_RAD VARIANCE_RAD2
 *     Sends one set-heading fix with its variance (0 = exact).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "dds/dds.h"
#include "headingd.h"
#include "ros2_msgs.h"

static double mono_s(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static double wall_s(void) {
  struct timespec ts;
  clock_gettime(CLOCK_REALTIME, &ts);
  return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static double stamp_of(const builtin_interfaces_msg_dds__Time_* t) {
  return (double)t->sec + (double)t->nanosec * 1e-9;
}

static void print_array(const char* name, const double* v, int n) {
  printf(" %s=", name);
  for (int i = 0; i < n; ++i) printf("%s%.17g", i ? "," : "", v[i]);
}

static void print_gid(const unsigned char* data, int n) {
  for (int i = 0; i < n; ++i) printf("%02x", data[i]);
}

static dds_entity_t reader(dds_entity_t participant, const dds_topic_descriptor_t* desc, const char* name,
                           dds_reliability_kind_t reliability, dds_durability_kind_t durability, int depth) {
  const dds_entity_t topic = dds_create_topic(participant, desc, name, NULL, NULL);
  if (topic < 0) {
    fprintf(stderr, "ros_peer: create_topic %s: %s\n", name, dds_strretcode(-topic));
    exit(1);
  }
  dds_qos_t* qos = dds_create_qos();
  dds_qset_reliability(qos, reliability, DDS_MSECS(100));
  dds_qset_durability(qos, durability);
  dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, depth);
  const dds_entity_t r = dds_create_reader(participant, topic, qos, NULL);
  dds_delete_qos(qos);
  if (r < 0) {
    fprintf(stderr, "ros_peer: create_reader %s: %s\n", name, dds_strretcode(-r));
    exit(1);
  }
  return r;
}

static void print_imu(const char* label, const sensor_msgs_msg_dds__Imu_* m) {
  printf("%s stamp=%.9f frame=%s q=%.17g,%.17g,%.17g,%.17g", label, stamp_of(&m->header.stamp),
         m->header.frame_id ? m->header.frame_id : "", m->orientation.x, m->orientation.y, m->orientation.z,
         m->orientation.w);
  print_array("ocov", m->orientation_covariance, 9);
  const double w[3] = {m->angular_velocity.x, m->angular_velocity.y, m->angular_velocity.z};
  print_array("w", w, 3);
  print_array("wcov", m->angular_velocity_covariance, 9);
  print_array("acov", m->linear_acceleration_covariance, 9);
  printf("\n");
}

static const char* reliability_name(const dds_qos_t* qos) {
  dds_reliability_kind_t kind;
  dds_duration_t blocking;
  if (!dds_qget_reliability(qos, &kind, &blocking)) return "?";
  return kind == DDS_RELIABILITY_RELIABLE ? "reliable" : "best_effort";
}

static const char* durability_name(const dds_qos_t* qos) {
  dds_durability_kind_t kind;
  if (!dds_qget_durability(qos, &kind)) return "?";
  switch (kind) {
    case DDS_DURABILITY_VOLATILE:
      return "volatile";
    case DDS_DURABILITY_TRANSIENT_LOCAL:
      return "transient_local";
    default:
      return "other";
  }
}

static void print_endpoints(dds_entity_t r, const char* label) {
  void* samples[8] = {NULL};
  dds_sample_info_t info[8];
  const int n = dds_take(r, samples, info, 8, 8);
  for (int i = 0; i < n; ++i) {
    if (!info[i].valid_data) continue;
    const dds_builtintopic_endpoint_t* e = samples[i];
    printf("%s topic=%s type=%s reliability=%s durability=%s guid=", label, e->topic_name, e->type_name,
           reliability_name(e->qos), durability_name(e->qos));
    print_gid(e->key.v, 16);
    printf("\n");
  }
  if (n > 0) dds_return_loan(r, samples, n);
}

static int listen(dds_domainid_t domain, double seconds, const char* ns) {
  const dds_entity_t participant = dds_create_participant(domain, NULL, NULL);
  if (participant < 0) {
    fprintf(stderr, "ros_peer: create_participant: %s\n", dds_strretcode(-participant));
    return 1;
  }
  char imu_name[300], temperature_name[300];
  snprintf(imu_name, sizeof imu_name, "rt%s/imu/data", ns);
  snprintf(temperature_name, sizeof temperature_name, "rt%s/imu/temperature", ns);
  /* rclcpp's default QoS (reliable, volatile, keep last 10) and the sensor-data profile
   * (best effort, volatile, keep last 5). */
  const dds_entity_t imu_reliable = reader(participant, &sensor_msgs_msg_dds__Imu__desc, imu_name,
                                           DDS_RELIABILITY_RELIABLE, DDS_DURABILITY_VOLATILE, 10);
  const dds_entity_t imu_sensor = reader(participant, &sensor_msgs_msg_dds__Imu__desc, imu_name,
                                         DDS_RELIABILITY_BEST_EFFORT, DDS_DURABILITY_VOLATILE, 5);
  const dds_entity_t diagnostics = reader(participant, &diagnostic_msgs_msg_dds__DiagnosticArray__desc,
                                          "rt/diagnostics", DDS_RELIABILITY_RELIABLE, DDS_DURABILITY_VOLATILE, 10);
  const dds_entity_t temperature = reader(participant, &sensor_msgs_msg_dds__Temperature__desc, temperature_name,
                                          DDS_RELIABILITY_BEST_EFFORT, DDS_DURABILITY_VOLATILE, 5);
  /* As rmw reads it: reliable, transient local, so a late reader still gets it. */
  const dds_entity_t discovery =
      reader(participant, &rmw_dds_common_msg_dds__ParticipantEntitiesInfo__desc, "ros_discovery_info",
             DDS_RELIABILITY_RELIABLE, DDS_DURABILITY_TRANSIENT_LOCAL, 10);
  const dds_entity_t orientation = reader(participant, &headingd_msg_Orientation_desc, "headingd/orientation",
                                          DDS_RELIABILITY_BEST_EFFORT, DDS_DURABILITY_VOLATILE, 64);
  const dds_entity_t publications = dds_create_reader(participant, DDS_BUILTIN_TOPIC_DCPSPUBLICATION, NULL, NULL);
  const dds_entity_t subscriptions = dds_create_reader(participant, DDS_BUILTIN_TOPIC_DCPSSUBSCRIPTION, NULL, NULL);

  const double deadline = mono_s() + seconds;
  while (mono_s() < deadline) {
    int got = 0;
    void* samples[1] = {NULL};
    dds_sample_info_t info[1];
    const dds_entity_t imu_readers[2] = {imu_reliable, imu_sensor};
    for (int k = 0; k < 2; ++k) {
      samples[0] = NULL;
      const int n = dds_take(imu_readers[k], samples, info, 1, 1);
      if (n > 0 && info[0].valid_data) print_imu(k == 0 ? "imu_reliable" : "imu_sensor_data", samples[0]);
      if (n > 0) dds_return_loan(imu_readers[k], samples, n);
      got += n > 0;
    }
    samples[0] = NULL;
    int n = dds_take(diagnostics, samples, info, 1, 1);
    if (n > 0 && info[0].valid_data) {
      const diagnostic_msgs_msg_dds__DiagnosticArray_* a = samples[0];
      for (uint32_t i = 0; i < a->status._length; ++i) {
        const diagnostic_msgs_msg_dds__DiagnosticStatus_* s = &a->status._buffer[i];
        printf("diagnostic stamp=%.9f level=%u name=%s|hardware_id=%s|message=%s|", stamp_of(&a->header.stamp),
               (unsigned)s->level, s->name, s->hardware_id, s->message);
        for (uint32_t k = 0; k < s->values._length; ++k)
          printf("%s=%s;", s->values._buffer[k].key, s->values._buffer[k].value);
        printf("\n");
      }
    }
    if (n > 0) dds_return_loan(diagnostics, samples, n);
    got += n > 0;
    samples[0] = NULL;
    n = dds_take(temperature, samples, info, 1, 1);
    if (n > 0 && info[0].valid_data) {
      const sensor_msgs_msg_dds__Temperature_* t = samples[0];
      printf("temperature stamp=%.9f frame=%s celsius=%.6f variance=%g\n", stamp_of(&t->header.stamp),
             t->header.frame_id, t->temperature, t->variance);
    }
    if (n > 0) dds_return_loan(temperature, samples, n);
    got += n > 0;
    samples[0] = NULL;
    n = dds_take(discovery, samples, info, 1, 1);
    if (n > 0 && info[0].valid_data) {
      const rmw_dds_common_msg_dds__ParticipantEntitiesInfo_* p = samples[0];
      printf("discovery gid=");
      print_gid(p->gid.data, 16);
      for (uint32_t i = 0; i < p->node_entities_info_seq._length; ++i) {
        const rmw_dds_common_msg_dds__NodeEntitiesInfo_* node = &p->node_entities_info_seq._buffer[i];
        printf(" node=%s|%s readers=", node->node_namespace, node->node_name);
        for (uint32_t k = 0; k < node->reader_gid_seq._length; ++k) {
          printf(k ? "," : "");
          print_gid(node->reader_gid_seq._buffer[k].data, 16);
        }
        printf(" writers=");
        for (uint32_t k = 0; k < node->writer_gid_seq._length; ++k) {
          printf(k ? "," : "");
          print_gid(node->writer_gid_seq._buffer[k].data, 16);
        }
      }
      printf("\n");
    }
    if (n > 0) dds_return_loan(discovery, samples, n);
    got += n > 0;
    samples[0] = NULL;
    n = dds_take(orientation, samples, info, 1, 1);
    if (n > 0 && info[0].valid_data) {
      const headingd_msg_Orientation* o = samples[0];
      printf("orientation stamp=%.9f seq=%llu heading=%.17g variance=%.17g fixes=%llu yaw_offset=%.17g\n",
             stamp_of((const void*)&o->stamp), (unsigned long long)o->seq, o->heading_rad, o->heading_variance_rad2,
             (unsigned long long)o->heading_fixes, o->yaw_offset_rad);
    }
    if (n > 0) dds_return_loan(orientation, samples, n);
    got += n > 0;
    print_endpoints(publications, "publication");
    print_endpoints(subscriptions, "subscription");
    fflush(stdout);
    if (got == 0) dds_sleepfor(DDS_MSECS(2));
  }
  /* Everything is printed: a hang in the teardown below (Cyclone DDS 0.10's dds_delete has been
   * seen to block, cyclonedds#1916) loses nothing a caller reads. */
  printf("end listened=%.1f\n", seconds);
  fflush(stdout);
  dds_delete(participant);
  return 0;
}

static int odom(dds_domainid_t domain, const char* topic_name, const char* mode, double seconds, int twist_only) {
  const dds_entity_t participant = dds_create_participant(domain, NULL, NULL);
  if (participant < 0) return 1;
  const dds_entity_t topic = dds_create_topic(
      participant, twist_only ? &geometry_msgs_msg_dds__Twist__desc : &nav_msgs_msg_dds__Odometry__desc, topic_name,
      NULL, NULL);
  dds_qos_t* qos = dds_create_qos();
  dds_qset_reliability(qos, DDS_RELIABILITY_RELIABLE, DDS_MSECS(100));
  dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, 10);
  const dds_entity_t writer = dds_create_writer(participant, topic, qos, NULL);
  dds_delete_qos(qos);
  if (topic < 0 || writer < 0) return 1;
  /* An Orientation reader too, so that headingd's --wait-subscribers waits for us. */
  const dds_entity_t orientation_topic =
      dds_create_topic(participant, &headingd_msg_Orientation_desc, "headingd/orientation", NULL, NULL);
  dds_qos_t* best_effort = dds_create_qos();
  dds_qset_reliability(best_effort, DDS_RELIABILITY_BEST_EFFORT, 0);
  if (dds_create_reader(participant, orientation_topic, best_effort, NULL) < 0) return 1;
  dds_delete_qos(best_effort);
  long sent = 0;
  const double deadline = mono_s() + seconds;
  while (mono_s() < deadline) {
    nav_msgs_msg_dds__Odometry_ m;
    memset(&m, 0, sizeof m);
    double stamp = wall_s();
    if (strcmp(mode, "stale") == 0) stamp -= 60.0;
    if (strcmp(mode, "future") == 0) stamp += 60.0;
    m.header.stamp.sec = (int32_t)floor(stamp);
    m.header.stamp.nanosec = (uint32_t)((stamp - floor(stamp)) * 1e9);
    m.header.frame_id = "odom";
    m.child_frame_id = "base_link";
    m.pose.pose.orientation.w = 1.0;
    if (strcmp(mode, "moving") == 0) {
      m.twist.twist.linear.x = 1.0;
      m.twist.twist.angular.z = 0.2;
    } else if (strcmp(mode, "nan") == 0) {
      m.twist.twist.linear.x = NAN;
    }
    dds_write(writer, twist_only ? (const void*)&m.twist.twist : (const void*)&m);
    ++sent;
    dds_sleepfor(DDS_MSECS(50));
  }
  printf("odom: sent %ld %s messages on %s\n", sent, mode, topic_name);
  dds_delete(participant);
  return 0;
}

/* A reliable, keep-all HeadingCommand writer, once headingd's command reader has matched it. */
static dds_entity_t command_writer(dds_entity_t participant) {
  const dds_entity_t topic =
      dds_create_topic(participant, &headingd_msg_HeadingCommand_desc, "headingd/command", NULL, NULL);
  dds_qos_t* qos = dds_create_qos();
  dds_qset_reliability(qos, DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
  dds_qset_history(qos, DDS_HISTORY_KEEP_ALL, 0);
  const dds_entity_t writer = dds_create_writer(participant, topic, qos, NULL);
  dds_delete_qos(qos);
  if (topic < 0 || writer < 0) {
    /* Under DDS Security, access control refuses here what the permissions do not grant. */
    fprintf(stderr, "ros_peer: headingd/command %s: %s\n", topic < 0 ? "topic" : "writer",
            dds_strretcode(topic < 0 ? topic : writer));
    return -1;
  }
  dds_publication_matched_status_t matched = {0};
  const double wait_until = mono_s() + 15.0;
  while (matched.current_count == 0 && mono_s() < wait_until) {
    dds_get_publication_matched_status(writer, &matched);
    dds_sleepfor(DDS_MSECS(20));
  }
  if (matched.current_count == 0) {
    fprintf(stderr, "ros_peer: no headingd/command reader\n");
    return -1;
  }
  dds_sleepfor(DDS_MSECS(300));
  return writer;
}

static int write_set_heading(dds_entity_t writer, double heading_rad, double variance_rad2) {
  headingd_msg_HeadingCommand c;
  memset(&c, 0, sizeof c);
  const double now = wall_s();
  c.stamp.sec = (int32_t)floor(now);
  c.stamp.nanosec = (uint32_t)((now - floor(now)) * 1e9);
  c.kind = headingd_msg_COMMAND_SET_HEADING;
  c.heading_rad = heading_rad;
  c.heading_variance_rad2 = variance_rad2;
  return dds_write(writer, &c) < 0 ? 1 : 0;
}

/* N HeadingCommands with a NaN heading, at RATE per second, reliable and kept: every one reaches
 * headingd and every one must be refused. */
static int bad_commands(dds_domainid_t domain, long n, double rate) {
  const dds_entity_t participant = dds_create_participant(domain, NULL, NULL);
  if (participant < 0) return 1;
  const dds_entity_t writer = command_writer(participant);
  if (writer < 0) return 1;
  const double start = mono_s();
  for (long i = 0; i < n; ++i) {
    if (write_set_heading(writer, NAN, 0.0)) return 1;
    const double due = start + (double)(i + 1) / rate;
    while (mono_s() < due) dds_sleepfor(DDS_USECS(200));
  }
  dds_sleepfor(DDS_SECS(1)); /* let reliable delivery finish */
  printf("commands: sent %ld with a NaN heading\n", n);
  dds_delete(participant);
  return 0;
}

/* One set-heading fix with its variance (rad^2; 0 = exact), as a vehicle's localisation sends it. */
static int set_heading(dds_domainid_t domain, double heading_rad, double variance_rad2) {
  const dds_entity_t participant = dds_create_participant(domain, NULL, NULL);
  if (participant < 0) {
    fprintf(stderr, "ros_peer: create_participant: %s\n", dds_strretcode(-participant));
    return 1;
  }
  const dds_entity_t writer = command_writer(participant);
  if (writer < 0 || write_set_heading(writer, heading_rad, variance_rad2)) return 1;
  dds_sleepfor(DDS_MSECS(500)); /* let reliable delivery finish */
  printf("commands: set-heading %.17g rad, variance %.17g rad^2\n", heading_rad, variance_rad2);
  dds_delete(participant);
  return 0;
}

int main(int argc, char** argv) {
  if (argc == 5 && strcmp(argv[1], "bad-commands") == 0)
    return bad_commands((dds_domainid_t)atoi(argv[2]), atol(argv[3]), atof(argv[4]));
  if (argc == 5 && strcmp(argv[1], "set-heading") == 0)
    return set_heading((dds_domainid_t)atoi(argv[2]), atof(argv[3]), atof(argv[4]));
  if (argc >= 4 && strcmp(argv[1], "listen") == 0)
    return listen((dds_domainid_t)atoi(argv[2]), atof(argv[3]), argc > 4 ? argv[4] : "");
  if (argc == 6 && (strcmp(argv[1], "odom") == 0 || strcmp(argv[1], "twist") == 0))
    return odom((dds_domainid_t)atoi(argv[2]), argv[3], argv[4], atof(argv[5]), strcmp(argv[1], "twist") == 0);
  fprintf(stderr,
          "usage: ros_peer listen DOMAIN SECONDS [NAMESPACE] | ros_peer odom|twist DOMAIN TOPIC MODE SECONDS | "
          "ros_peer bad-commands DOMAIN N RATE | ros_peer set-heading DOMAIN HEADING_RAD VARIANCE_RAD2\n");
  return 64;
}
