#include "io/compressed_file.hpp"

#include <sys/stat.h>
#include <zlib.h>
#include <zstd.h>

#include <cerrno>
#include <cstring>
#include <thread>
#include <vector>

#include "io/spsc_ring.hpp"

namespace headingd::drivers {
namespace {

thread_local std::string last_error;

constexpr unsigned char kZstdMagic[4] = {0x28, 0xB5, 0x2F, 0xFD};
constexpr unsigned char kGzipMagic[2] = {0x1F, 0x8B};
constexpr std::size_t kInputBytes = 1 << 17;

ssize_t failed(std::string why) {
  last_error = std::move(why);
  errno = EBADMSG;
  return -1;
}

// Input common to the readers: the bytes already taken to look at the magic number, then the file.
struct Input {
  std::FILE* file;
  std::vector<unsigned char> bytes = std::vector<unsigned char>(kInputBytes);
  std::size_t begin = 0, end = 0;
  bool eof = false;
  // Refills when empty; false at the end of the file (or on an error, with last_error set).
  bool refill(bool& error) {
    if (begin < end) return true;
    begin = 0;
    end = std::fread(bytes.data(), 1, bytes.size(), file);
    if (end == 0) {
      if (std::ferror(file) != 0) {
        last_error = std::string("read error: ") + std::strerror(errno);
        error = true;
      }
      eof = true;
      return false;
    }
    return true;
  }
};

struct PlainReader {
  Input in;
};

ssize_t plain_read(void* cookie, char* out, std::size_t size) {
  auto& in = static_cast<PlainReader*>(cookie)->in;
  if (in.begin < in.end) {
    const std::size_t n = std::min(size, in.end - in.begin);
    std::memcpy(out, in.bytes.data() + in.begin, n);
    in.begin += n;
    return static_cast<ssize_t>(n);
  }
  const std::size_t n = std::fread(out, 1, size, in.file);
  if (n == 0 && std::ferror(in.file) != 0) return -1;
  return static_cast<ssize_t>(n);
}

struct ZstdReader {
  Input in;
  ZSTD_DCtx* context = ZSTD_createDCtx();
  bool frame_open = false;
};

ssize_t zstd_read(void* cookie, char* out, std::size_t size) {
  auto& z = *static_cast<ZstdReader*>(cookie);
  ZSTD_outBuffer output{out, size, 0};
  while (output.pos == 0) {
    bool error = false;
    if (!z.in.refill(error)) {
      if (error) return failed(last_error);
      if (z.frame_open) return failed("truncated zstd stream (the file was cut short, or is still being written)");
      return 0;
    }
    ZSTD_inBuffer input{z.in.bytes.data(), z.in.end, z.in.begin};
    const std::size_t result = ZSTD_decompressStream(z.context, &output, &input);
    z.in.begin = input.pos;
    if (ZSTD_isError(result) != 0) return failed(std::string("corrupt zstd data: ") + ZSTD_getErrorName(result));
    z.frame_open = result != 0;
  }
  return static_cast<ssize_t>(output.pos);
}

struct GzipReader {
  Input in;
  z_stream stream{};
  bool member_open = false;
};

ssize_t gzip_read(void* cookie, char* out, std::size_t size) {
  auto& g = *static_cast<GzipReader*>(cookie);
  g.stream.next_out = reinterpret_cast<Bytef*>(out);
  g.stream.avail_out = static_cast<uInt>(std::min<std::size_t>(size, 1u << 30));
  while (g.stream.avail_out == size) {
    bool error = false;
    if (!g.in.refill(error)) {
      if (error) return failed(last_error);
      if (g.member_open) return failed("truncated gzip stream (the file was cut short, or is still being written)");
      return 0;
    }
    if (!g.member_open) {
      inflateReset(&g.stream);  // the next member of a concatenated file
      g.member_open = true;
    }
    g.stream.next_in = g.in.bytes.data() + g.in.begin;
    g.stream.avail_in = static_cast<uInt>(g.in.end - g.in.begin);
    const int result = inflate(&g.stream, Z_NO_FLUSH);
    g.in.begin = g.in.end - g.stream.avail_in;
    if (result == Z_STREAM_END)
      g.member_open = false;
    else if (result != Z_OK && result != Z_BUF_ERROR)
      return failed(std::string("corrupt gzip data: ") + (g.stream.msg != nullptr ? g.stream.msg : "inflate failed"));
  }
  return static_cast<ssize_t>(size - g.stream.avail_out);
}

template <typename Reader>
int close_reader(void* cookie) {
  auto* reader = static_cast<Reader*>(cookie);
  const int result = std::fclose(reader->in.file);
  if constexpr (std::is_same_v<Reader, ZstdReader>) ZSTD_freeDCtx(reader->context);
  if constexpr (std::is_same_v<Reader, GzipReader>) inflateEnd(&reader->stream);
  delete reader;
  return result;
}

// Decompression on a thread of its own, a few megabytes ahead of the reader: a replay then
// decompresses, parses and estimates at once instead of decompressing between parses. The
// decompressor's own reader (zstd_read, gzip_read) runs on that thread; its text arrives here
// in order, and an error after it, with the decompressor's words, once the text is taken.
struct Chunk {
  std::vector<char> bytes = std::vector<char>(1 << 20);
  std::size_t size = 0;
  bool end = false;   // nothing after this chunk's bytes: the end, or `error`
  std::string error;  // the decompressor's words
  int error_number = 0;
};

struct ThreadedReader {
  ThreadedReader(void* reader, cookie_read_function_t* read, cookie_close_function_t* close)
      : inner(reader), inner_read(read), inner_close(close) {}
  void* inner;
  cookie_read_function_t* inner_read;
  cookie_close_function_t* inner_close;
  SpscRing<Chunk> ring{4};
  std::thread worker;
  Chunk* current = nullptr;  // consumer side
  std::size_t offset = 0;
};

void decompress_ahead(ThreadedReader& t) {
  while (Chunk* chunk = t.ring.next_empty()) {
    chunk->size = 0;
    chunk->end = false;
    chunk->error.clear();
    while (chunk->size < chunk->bytes.size()) {
      const ssize_t n = t.inner_read(t.inner, chunk->bytes.data() + chunk->size, chunk->bytes.size() - chunk->size);
      if (n > 0) {
        chunk->size += static_cast<std::size_t>(n);
        continue;
      }
      if (n < 0) {
        chunk->error_number = errno;
        chunk->error = last_error.empty() ? std::string("read error: ") + std::strerror(errno) : last_error;
      }
      chunk->end = true;
      break;
    }
    const bool last = chunk->end;
    t.ring.publish();
    if (last) return;
  }
}

ssize_t threaded_read(void* cookie, char* out, std::size_t size) {
  auto& t = *static_cast<ThreadedReader*>(cookie);
  while (true) {
    if (t.current != nullptr && t.offset < t.current->size) {
      const std::size_t n = std::min(size, t.current->size - t.offset);
      std::memcpy(out, t.current->bytes.data() + t.offset, n);
      t.offset += n;
      return static_cast<ssize_t>(n);
    }
    if (t.current != nullptr && t.current->end) {
      if (t.current->error.empty()) return 0;
      last_error = t.current->error;
      errno = t.current->error_number;
      return -1;
    }
    if (t.current != nullptr) t.ring.give_back();
    if (!t.worker.joinable()) t.worker = std::thread([&t] { decompress_ahead(t); });
    t.current = &t.ring.next_filled();
    t.offset = 0;
  }
}

int threaded_close(void* cookie) {
  auto* t = static_cast<ThreadedReader*>(cookie);
  t->ring.close();
  if (t->worker.joinable()) t->worker.join();
  const int result = t->inner_close(t->inner);
  delete t;
  return result;
}

template <typename Reader>
std::FILE* wrap(Reader* reader, cookie_read_function_t* read, bool threaded) {
  cookie_io_functions_t functions{};
  void* cookie = reader;
  functions.read = read;
  functions.close = &close_reader<Reader>;
  if (threaded) {
    cookie = new ThreadedReader(reader, read, &close_reader<Reader>);
    functions.read = &threaded_read;
    functions.close = &threaded_close;
  }
  std::FILE* file = fopencookie(cookie, "rb", functions);
  if (file == nullptr) functions.close(cookie);
  return file;
}

struct ZstdWriter {
  std::FILE* file;
  ZSTD_CCtx* context = ZSTD_createCCtx();
  std::vector<char> out = std::vector<char>(ZSTD_CStreamOutSize());
  bool drain(ZSTD_inBuffer& input, ZSTD_EndDirective mode) {
    while (true) {
      ZSTD_outBuffer output{out.data(), out.size(), 0};
      const std::size_t left = ZSTD_compressStream2(context, &output, &input, mode);
      if (ZSTD_isError(left) != 0) {
        errno = EIO;
        return false;
      }
      if (output.pos > 0 && std::fwrite(out.data(), 1, output.pos, file) != output.pos) return false;
      if (left == 0 && input.pos == input.size) return true;
    }
  }
};

ssize_t zstd_write(void* cookie, const char* data, std::size_t size) {
  auto& z = *static_cast<ZstdWriter*>(cookie);
  ZSTD_inBuffer input{data, size, 0};
  // Flushed: whatever has been written is complete blocks on disk, readable after a crash.
  if (!z.drain(input, ZSTD_e_flush) || std::fflush(z.file) != 0) return -1;
  return static_cast<ssize_t>(size);
}

int zstd_close(void* cookie) {
  auto* z = static_cast<ZstdWriter*>(cookie);
  ZSTD_inBuffer nothing{nullptr, 0, 0};
  const bool ended = z->drain(nothing, ZSTD_e_end);
  const int error = errno;
  const int closed = std::fclose(z->file);
  ZSTD_freeCCtx(z->context);
  delete z;
  if (!ended) errno = error;
  return ended ? closed : -1;
}

}  // namespace

std::string decompression_error() { return last_error; }

bool wants_zstd(const std::string& path) { return path.size() > 4 && path.compare(path.size() - 4, 4, ".zst") == 0; }

namespace {

std::FILE* decompressing(std::FILE* file, bool threaded, bool* compressed = nullptr) {
  last_error.clear();
  unsigned char head[4] = {};
  const std::size_t got = std::fread(head, 1, sizeof head, file);
  const auto take_head = [&](Input& in) {
    std::memcpy(in.bytes.data(), head, got);
    in.end = got;
  };
  const bool zstd = got == 4 && std::memcmp(head, kZstdMagic, 4) == 0;
  const bool gzip = !zstd && got >= 2 && std::memcmp(head, kGzipMagic, 2) == 0;
  if (compressed != nullptr) *compressed = zstd || gzip;
  if (zstd) {
    auto* reader = new ZstdReader{Input{file}};
    take_head(reader->in);
    return wrap(reader, &zstd_read, threaded);
  }
  if (gzip) {
    auto* reader = new GzipReader{Input{file}};
    take_head(reader->in);
    if (inflateInit2(&reader->stream, 15 + 16) != Z_OK) {  // 15: the largest window; +16: gzip headers
      close_reader<GzipReader>(reader);
      errno = ENOMEM;
      return nullptr;
    }
    return wrap(reader, &gzip_read, threaded);
  }
  // Plain: a regular file is read on a thread of its own too (the copies out of the page
  // cache then leave the parsing thread); other seekable ones as they are.
  if (!threaded && std::fseek(file, 0, SEEK_SET) == 0) return file;
  auto* reader = new PlainReader{Input{file}};
  take_head(reader->in);
  return wrap(reader, &plain_read, threaded);
}

}  // namespace

std::FILE* decompressing(std::FILE* file) { return decompressing(file, false); }

std::FILE* open_for_reading(const std::string& path, bool* compressed) {
  std::FILE* file = std::fopen(path.c_str(), "rb");
  if (file == nullptr) return nullptr;
  // A regular file decompresses on a thread of its own; a pipe is read where a stop can end a
  // read that waits.
  struct stat info {};
  const bool regular = ::fstat(::fileno(file), &info) == 0 && S_ISREG(info.st_mode);
  return decompressing(file, regular, compressed);
}

std::FILE* zstd_writer(std::FILE* file, int level) {
  auto* writer = new ZstdWriter{file};
  ZSTD_CCtx_setParameter(writer->context, ZSTD_c_compressionLevel, level);
  ZSTD_CCtx_setParameter(writer->context, ZSTD_c_checksumFlag, 1);  // flipped bytes are found, not replayed
  cookie_io_functions_t functions{};
  functions.write = &zstd_write;
  functions.close = &zstd_close;
  std::FILE* wrapped = fopencookie(writer, "wb", functions);
  if (wrapped == nullptr) {
    zstd_close(writer);
    return nullptr;
  }
  std::setvbuf(wrapped, nullptr, _IONBF, 0);  // CsvOut buffers; every write it makes is a flush point
  return wrapped;
}

}  // namespace headingd::drivers
