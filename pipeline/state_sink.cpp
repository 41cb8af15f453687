#include "pipeline/state_sink.hpp"

#include <limits>

#include "dds/dds_participant.hpp"
#include "io/state_file.hpp"
#include "service/log.hpp"

namespace headingd::pipeline {
namespace {

app::SavedState to_saved(const core::LearnedState& learned) {
  app::SavedState state;
  state.bias_dps = learned.bias_dps;
  state.bias_sigma_dps = learned.bias_sigma_dps.allFinite() ? learned.bias_sigma_dps : core::Vec3::Constant(0.01);
  state.temp_c = std::numeric_limits<double>::quiet_NaN();
  state.sigma_still_dps = learned.sigma_still_dps;
  state.arw_dps_rt_hz = learned.arw_dps_rt_hz;
  state.temperature_sums = learned.temperature_sums;
  state.temperature_points = learned.temperature_points;
  state.saved_unix_s = app::wall_now_s();
  return state;
}

core::LearnedState to_learned(const app::SavedState& saved) {
  core::LearnedState learned;
  learned.bias_dps = saved.bias_dps;
  learned.bias_sigma_dps = saved.bias_sigma_dps;
  learned.sigma_still_dps = saved.sigma_still_dps;
  learned.arw_dps_rt_hz = saved.arw_dps_rt_hz;
  learned.temperature_sums = saved.temperature_sums;
  learned.temperature_points = saved.temperature_points;
  return learned;
}

}  // namespace

StateSink::StateSink(std::string path, double interval_s) : path_(std::move(path)), interval_(interval_s) {}

void StateSink::save(const core::Estimator& estimator) {
  if (estimator.in_startup()) return;
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

void restore_state(core::Estimator& estimator, const std::string& path) {
  try {
    estimator.restore(to_learned(app::load_state(path)));
    app::log(app::LogPriority::Info, "state", "bias restored from " + path);
  } catch (const app::StateError& error) {
    app::log(app::LogPriority::Notice, "state", error.what());
  }
}

}  // namespace headingd::pipeline
