/* A second reader of a Linux IIO gyro, written against libiio (Analog Devices' library, not
 * ours): it finds the device by name through libiio's local backend, enables the three angular
 * rate channels and the timestamp, and reads COUNT scans through libiio's buffer. libiio lays
 * the scan out and decodes each channel (endianness, shift, sign, padding before the 64-bit
 * timestamp) from the sysfs "type" attributes by its own code; this program then applies the
 * ABI's arithmetic on top: (raw + offset) * scale in rad/s, turned into the platform's frame by
 * in_anglvel_mount_matrix (rows as the file lists them, Documentation/ABI/testing/sysfs-bus-iio).
 *   iio_libiio_reader DEVICE COUNT
 * prints "time_s,gx_dps,gy_dps,gz_dps" and one line per scan, as headingd records them.
 * libiio's local backend reads /sys/bus/iio and /dev only: the test runs it in a mount
 * namespace where a fake tree is bound over both. */
#include <errno.h>
#include <iio.h>
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char* const kAxes[3] = {"anglvel_x", "anglvel_y", "anglvel_z"};

static int fail(const char* what, int err) {
  char text[256];
  iio_strerror(err, text, sizeof text);
  fprintf(stderr, "iio_libiio_reader: %s: %s\n", what, text);
  return 1;
}

/* A channel attribute as a double; `fallback` where the device has no such attribute. */
static double attribute_or(const struct iio_channel* channel, const char* name, double fallback) {
  double value = fallback;
  if (iio_channel_find_attr(channel, name) && iio_channel_attr_read_double(channel, name, &value) < 0) return fallback;
  return value;
}

/* "a, b, c; d, e, f; g, h, i" into m (row major); the identity where there is none. */
static int mount_matrix(const struct iio_channel* channel, double m[9]) {
  for (int i = 0; i < 9; ++i) m[i] = i % 4 == 0 ? 1.0 : 0.0;
  if (!iio_channel_find_attr(channel, "mount_matrix")) return 0;
  char text[256];
  if (iio_channel_attr_read(channel, "mount_matrix", text, sizeof text) < 0) return -1;
  const char* at = text;
  for (int i = 0; i < 9; ++i) {
    char* end = NULL;
    m[i] = strtod(at, &end);
    if (end == at) return -1;
    at = end;
    while (*at == ',' || *at == ';' || *at == ' ') ++at;
  }
  return 0;
}

/* One channel's sample, converted by libiio to a host-order integer of the channel's storage size
 * (sign-extended within it where signed), widened here to 64 bits. */
#if __BYTE_ORDER__ != __ORDER_LITTLE_ENDIAN__
#error "sample_of reads libiio's host-order bytes as little-endian"
#endif
static int64_t sample_of(const struct iio_channel* channel, const void* src) {
  const struct iio_data_format* format = iio_channel_get_data_format(channel);
  const unsigned bytes = format->length / 8;
  unsigned char dst[8] = {0};
  iio_channel_convert(channel, dst, src);
  uint64_t value = 0;
  memcpy(&value, dst, bytes);
  if (format->is_signed && bytes < 8 && ((value >> (8 * bytes - 1)) & 1u)) value |= ~UINT64_C(0) << (8 * bytes);
  return (int64_t)value;
}

int main(int argc, char** argv) {
  if (argc != 3) {
    fprintf(stderr, "usage: iio_libiio_reader DEVICE COUNT\n");
    return 64;
  }
  const long count = strtol(argv[2], NULL, 10);
  struct iio_context* context = iio_create_local_context();
  if (!context) return fail("local context", errno);
  struct iio_device* device = iio_context_find_device(context, argv[1]);
  if (!device) {
    fprintf(stderr, "iio_libiio_reader: no device %s\n", argv[1]);
    return 1;
  }
  const struct iio_channel* axes[3];
  double scale[3], offset[3];
  for (int i = 0; i < 3; ++i) {
    struct iio_channel* channel = iio_device_find_channel(device, kAxes[i], false);
    if (!channel || !iio_channel_is_scan_element(channel)) {
      fprintf(stderr, "iio_libiio_reader: %s is no scan element\n", kAxes[i]);
      return 1;
    }
    iio_channel_enable(channel);
    axes[i] = channel;
    scale[i] = attribute_or(channel, "scale", 1.0);
    offset[i] = attribute_or(channel, "offset", 0.0);
  }
  struct iio_channel* timestamp = iio_device_find_channel(device, "timestamp", false);
  if (!timestamp) {
    fprintf(stderr, "iio_libiio_reader: no timestamp channel\n");
    return 1;
  }
  iio_channel_enable(timestamp);
  double mount[9];
  if (mount_matrix(axes[0], mount) < 0) {
    fprintf(stderr, "iio_libiio_reader: unreadable mount_matrix\n");
    return 1;
  }
  fprintf(stderr, "iio_libiio_reader: %zd bytes per scan\n", iio_device_get_sample_size(device));

  struct iio_buffer* buffer = iio_device_create_buffer(device, 16, false);
  if (!buffer) return fail("create buffer", errno);
  printf("time_s,gx_dps,gy_dps,gz_dps\n");
  const double deg = 180.0 / M_PI;
  long done = 0;
  while (done < count) {
    const ssize_t got = iio_buffer_refill(buffer);
    if (got < 0) return fail("refill", (int)-got);
    const ptrdiff_t step = iio_buffer_step(buffer);
    const char* end = iio_buffer_end(buffer);
    const char* t_at = iio_buffer_first(buffer, timestamp);
    const char* at[3];
    for (int i = 0; i < 3; ++i) at[i] = iio_buffer_first(buffer, axes[i]);
    for (; t_at < end && done < count; t_at += step, ++done) {
      double sensor[3];
      for (int i = 0; i < 3; ++i) {
        sensor[i] = ((double)sample_of(axes[i], at[i]) + offset[i]) * scale[i];
        at[i] += step;
      }
      const int64_t t_ns = sample_of(timestamp, t_at);
      printf("%" PRId64 ".%09" PRId64, t_ns / 1000000000, t_ns % 1000000000);
      for (int row = 0; row < 3; ++row) {
        const double v = mount[3 * row] * sensor[0] + mount[3 * row + 1] * sensor[1] + mount[3 * row + 2] * sensor[2];
        printf(",%.17g", v * deg);
      }
      printf("\n");
    }
  }
  iio_buffer_destroy(buffer);
  iio_context_destroy(context);
  return 0;
}
