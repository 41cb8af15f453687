#pragma once
// Recordings compressed with zstd or gzip, read and written as if they were plain text: when
// reading, the format is told by the magic number (zstd 28 B5 2F FD, gzip 1F 8B), never by the
// name; when writing, a name ending in ".zst" compresses. Both are FILE* streams (glibc's
// fopencookie), so LineReader and CsvOut work on them unchanged and report lines of the
// uncompressed text.
#include <cstdio>
#include <string>

namespace headingd::drivers {

// Opens `path` for reading, decompressing when its magic number says so; a regular file,
// plain or not, is read on a thread of its own, a few megabytes ahead. nullptr with errno set
// when it cannot be opened. `compressed`, if given, says whether it decompresses.
std::FILE* open_for_reading(const std::string& path, bool* compressed = nullptr);
// As open_for_reading, for a stream already open (pipes, tests).
std::FILE* decompressing(std::FILE* file);

// Wraps an open file for writing: zstd-compressed, flushed to complete blocks at every write
// (CsvOut writes whole buffers, and the recording sink flushes once a second), ended properly
// on fclose. Takes ownership of `file`.
std::FILE* zstd_writer(std::FILE* file, int level = 3);
bool wants_zstd(const std::string& path);

// The decompressor's words for the last read error on this thread (empty when none): "corrupt
// zstd data: ...", "truncated zstd stream", "corrupt gzip data: ...".
std::string decompression_error();

}  // namespace headingd::drivers
