#pragma once
// Reads a recording on a second thread while the estimator runs on this one: the parse, the
// larger half of a replay's work, no longer waits for the estimator and the estimator no longer
// waits for the parse. Blocks of a few thousand samples go through a bounded
// single-producer/single-consumer ring (io/spsc_ring; the reader stops when it is full).
//
// The wrapped source's contract holds unchanged: every good sample arrives before the
// InputError that followed it, which is rethrown as it was thrown (same type, same text).
// For files only (plain or compressed): a pipe could leave the reader blocked at close.
#include <cstdint>
#include <exception>
#include <functional>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "core/sample_source.hpp"
#include "io/spsc_ring.hpp"

namespace headingd::pipeline {

class ReadAheadSource final : public core::SampleSource {
 public:
  using Fraction = std::function<std::optional<double>()>;
  // `fraction`, if given, is how much of the file the reader has taken; it is asked on the
  // reading thread after each block, and fraction_read() returns the latest answer.
  explicit ReadAheadSource(core::SampleSource& inner, Fraction fraction = {}, std::size_t block_samples = 4096,
                           std::size_t blocks = 8);
  ~ReadAheadSource() override;
  ReadAheadSource(const ReadAheadSource&) = delete;
  ReadAheadSource& operator=(const ReadAheadSource&) = delete;

  std::size_t read(std::span<core::Sample> out) override;
  // A view into the block being handed out: the estimator reads the samples where the reader
  // thread put them.
  std::span<const core::Sample> next(std::span<core::Sample> scratch) override;
  void close() override;
  std::string describe() const override { return inner_.describe(); }  // fixed at open
  // As of the block being handed out (the reader runs ahead of it).
  core::SourceHealth health() const override { return health_; }
  std::string counters_text() const override { return counters_; }
  double nominal_rate_hz() const override { return inner_.nominal_rate_hz(); }
  std::optional<double> fraction_read() const { return fraction_read_; }

 private:
  struct Block {
    std::vector<core::Sample> samples;
    std::size_t count = 0;
    bool end = false;          // the source ended after these samples (or without any)
    std::exception_ptr error;  // what the source threw after them
    core::SourceHealth health;
    std::string counters;
    std::optional<double> fraction;
  };

  void produce();
  bool take_next_block();  // false once the source has ended

  core::SampleSource& inner_;
  Fraction fraction_;
  drivers::SpscRing<Block> ring_;
  std::thread reader_;
  bool closed_ = false;

  // This side only.
  Block* current_ = nullptr;
  std::size_t offset_ = 0;  // samples of current_ already handed out
  bool ended_ = false;
  core::SourceHealth health_;
  std::string counters_;
  std::optional<double> fraction_read_;
};

}  // namespace headingd::pipeline
