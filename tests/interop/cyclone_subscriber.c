/* A subscriber built on Eclipse Cyclone DDS, a second DDS implementation, with types that
 * Cyclone's idlc generates from the same IDL files: proof that a non-Fast-DDS reader, and hence a
 * ROS 2 node, can read headingd's Orientation topic and the ROS 2-named Imu topic.
 * Usage: cyclone_subscriber DOMAIN ORIENTATION_TOPIC IMU_TOPIC MIN_MESSAGES TIMEOUT_S [DEADLINE_MS]
 * With DEADLINE_MS both readers request that deadline: Cyclone matches them only with a writer
 * that offers a deadline at least as short. */
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "dds/dds.h"
#include "headingd.h"
#include "ros2_msgs.h"

static double now_s(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

int main(int argc, char** argv) {
  if (argc != 6 && argc != 7) {
    fprintf(stderr,
            "usage: cyclone_subscriber DOMAIN ORIENTATION_TOPIC IMU_TOPIC MIN_MESSAGES TIMEOUT_S [DEADLINE_MS]\n");
    return 64;
  }
  const dds_domainid_t domain = (dds_domainid_t)atoi(argv[1]);
  const long wanted = atol(argv[4]);
  const double timeout_s = atof(argv[5]);
  const dds_entity_t participant = dds_create_participant(domain, NULL, NULL);
  if (participant < 0) {
    fprintf(stderr, "cyclone: create_participant: %s\n", dds_strretcode(-participant));
    return 1;
  }
  const dds_entity_t orientation_topic =
      dds_create_topic(participant, &headingd_msg_Orientation_desc, argv[2], NULL, NULL);
  const dds_entity_t imu_topic = dds_create_topic(participant, &sensor_msgs_msg_dds__Imu__desc, argv[3], NULL, NULL);
  if (orientation_topic < 0 || imu_topic < 0) {
    fprintf(stderr, "cyclone: create_topic failed\n");
    return 1;
  }
  dds_qos_t* qos = dds_create_qos();
  dds_qset_reliability(qos, DDS_RELIABILITY_BEST_EFFORT, 0);
  if (argc == 7) dds_qset_deadline(qos, DDS_MSECS(atol(argv[6])));
  const dds_entity_t orientation_reader = dds_create_reader(participant, orientation_topic, qos, NULL);
  const dds_entity_t imu_reader = dds_create_reader(participant, imu_topic, qos, NULL);
  dds_delete_qos(qos);

  long orientations = 0, imus = 0;
  double heading = 0.0, lin_acc_cov0 = 0.0;
  unsigned long long last_seq = 0;
  char frame_id[64] = "";
  const double deadline = now_s() + timeout_s;
  while ((orientations < wanted || imus < wanted) && now_s() < deadline) {
    void* samples[1] = {NULL};
    dds_sample_info_t info[1];
    int n = dds_take(orientation_reader, samples, info, 1, 1);
    if (n > 0 && info[0].valid_data) {
      const headingd_msg_Orientation* o = samples[0];
      ++orientations;
      heading = o->heading_rad;
      last_seq = (unsigned long long)o->seq;
    }
    if (n > 0) dds_return_loan(orientation_reader, samples, n);
    samples[0] = NULL;
    n = dds_take(imu_reader, samples, info, 1, 1);
    if (n > 0 && info[0].valid_data) {
      const sensor_msgs_msg_dds__Imu_* m = samples[0];
      ++imus;
      lin_acc_cov0 = m->linear_acceleration_covariance[0];
      snprintf(frame_id, sizeof frame_id, "%s", m->header.frame_id ? m->header.frame_id : "");
    }
    if (n > 0) dds_return_loan(imu_reader, samples, n);
    if (n <= 0) dds_sleepfor(DDS_MSECS(2));
  }
  printf(
      "cyclone: %ld Orientation (last seq %llu, heading %.6f rad), %ld Imu (frame_id '%s', "
      "linear_acceleration_covariance[0] %g)\n",
      orientations, last_seq, heading, imus, frame_id, lin_acc_cov0);
  dds_delete(participant);
  return (orientations >= wanted && imus >= wanted) ? 0 : 1;
}
