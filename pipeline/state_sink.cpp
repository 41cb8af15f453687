#include "pipeline/state_sink.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "dds/dds_participant.hpp"
#include "io/state_file.hpp"
#include "service/log.hpp"

namespace headingd::pipeline {
namespace {

app::SavedState to_saved(const core::LearnedState& learned) {
  app::SavedState state;
  static_cast<core::LearnedState&>(state) = learned;
  state.saved_unix_s = app::wall_now_s();
  return state;
}

}  // namespace

StateSink::StateSink(std::string path, double interval_s) : path_(std::move(path)), interval_(interval_s) {}

void StateSink::save(const core::Estimator& estimator) {
  // Nothing learned yet: the file stays as it was found (a stop or a bad recording before the
  // first sample once wrote a zero bias over it; service.systemd_boot found it).
  if (estimator.samples() == 0 || estimator.in_startup()) return;
  try {
    app::save_state(path_, to_saved(estimator.learned()));
  } catch (const app::StateError& error) {
    app::log(app::LogPriority::Warning, "state write", error.what());
  }
}

void StateSink::batch_done(const core::Estimator& estimator, const core::SampleSource& /*source*/) {
  const auto now = std::chrono::steady_clock::now();
  if (now - last_save_ < interval_) return;
  last_save_ = now;
  save(estimator);
}

void StateSink::finish(const core::Estimator& estimator, const core::SampleSource& /*source*/) { save(estimator); }

void restore_state(core::Estimator& estimator, const std::string& path, bool with_heading) {
  try {
    const app::SavedState saved = app::load_state(path);
    estimator.restore_after_restart(saved, with_heading);
    std::string saved_at;
    if (std::isfinite(saved.temp_c) && estimator.method() == core::Method::Auto) {  // the paper's carry nothing
      char text[96];
      std::snprintf(text, sizeof text, " (saved at %.1f degC: carried to the temperature read at start)", saved.temp_c);
      saved_at = text;
    }
    app::log(app::LogPriority::Info, "state",
             std::string("bias ") + (with_heading && std::isfinite(saved.heading_deg) ? "and heading " : "") +
                 "restored from " + path + saved_at);
  } catch (const app::StateError& error) {
    app::log(app::LogPriority::Notice, "state", error.what());
  } catch (const std::invalid_argument& error) {
    app::log(app::LogPriority::Warning, "state", "state file " + path + ": " + error.what() + "; ignored");
  }
}

}  // namespace headingd::pipeline
