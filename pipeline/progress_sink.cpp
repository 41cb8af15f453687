#include "pipeline/progress_sink.hpp"

#include <unistd.h>

#include <cstdio>

namespace headingd::pipeline {
namespace {
constexpr double kFirstDrawS = 2.0;  // short replays never show a line
constexpr double kRedrawS = 0.5;
}  // namespace

ProgressSink::ProgressSink(Fraction fraction) : fraction_(std::move(fraction)) {}

bool ProgressSink::wanted() { return ::isatty(STDERR_FILENO) == 1; }

void ProgressSink::batch_done(const core::Estimator& /*estimator*/, const core::SampleSource& source) {
  const auto now = Clock::now();
  const double elapsed_s = std::chrono::duration<double>(now - start_).count();
  if (elapsed_s < kFirstDrawS || std::chrono::duration<double>(now - last_draw_).count() < kRedrawS) return;
  last_draw_ = now;
  const auto samples = static_cast<double>(source.health().samples);
  char line[160];
  int n = std::snprintf(line, sizeof line, "\r  %.1f M samples, %.2f M/s", samples / 1e6, samples / elapsed_s / 1e6);
  if (const auto done = fraction_ ? fraction_() : std::nullopt; done && *done > 0.0) {
    const double left_s = elapsed_s * (1.0 - *done) / *done;
    n += std::snprintf(line + n, sizeof line - static_cast<std::size_t>(n), ", %.0f %% done, %.0f s left",
                       *done * 100.0, left_s);
  }
  std::fprintf(stderr, "%s\033[K", line);
  std::fflush(stderr);
  drawn_ = true;
}

void ProgressSink::finish(const core::Estimator& /*estimator*/, const core::SampleSource& /*source*/) {
  if (drawn_) std::fprintf(stderr, "\r\033[K");  // the summary takes the line
}

}  // namespace headingd::pipeline
