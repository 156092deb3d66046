#include "loop/publish_pace.h"

namespace kane_sim {
namespace {

double seconds(PublishPace::Clock::duration d) { return std::chrono::duration<double>(d).count(); }

}  // namespace

void PublishPace::start(Clock::time_point now, double sim_time) {
  last_publish_wall_ = window_start_wall_ = now;
  last_publish_sim_ = window_start_sim_ = sim_time;
}

double PublishPace::published(Clock::time_point now, double sim_time) {
  const double wall = seconds(now - last_publish_wall_);
  if (wall > 0) real_time_factor_ = (sim_time - last_publish_sim_) / wall;
  last_publish_wall_ = now;
  last_publish_sim_ = sim_time;
  return real_time_factor_;
}

double PublishPace::sinceLastPublish(Clock::time_point now) const {
  return seconds(now - last_publish_wall_);
}

double PublishPace::windowWall(Clock::time_point now) const {
  return seconds(now - window_start_wall_);
}

double PublishPace::closeWindow(Clock::time_point now, double sim_time) {
  const double covered = sim_time - window_start_sim_;
  window_start_wall_ = now;
  window_start_sim_ = sim_time;
  return covered;
}

}  // namespace kane_sim
