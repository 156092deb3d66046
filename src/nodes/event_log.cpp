#include "event_log.h"

#include <ros/console.h>

namespace kane_sim {

void logSimEvent(const SimEvent& event, LoopDiagnostics* diagnostics) {
  const char* text = event.message.c_str();
  switch (event.kind) {
    case SimEvent::Kind::kCommandRejected:
      ROS_WARN_THROTTLE(1.0, "kane_sim: %s", text);
      break;
    case SimEvent::Kind::kCommandClamped:
      ROS_WARN_THROTTLE(1.0, "kane_sim: %s", text);
      break;
    case SimEvent::Kind::kStepRefused:
      diagnostics->stepRefused(event.message);
      ROS_ERROR_THROTTLE(1.0,
                         "kane_sim: %s. The last good state stays published; lower the torque or "
                         "call the reset service",
                         text);
      break;
    case SimEvent::Kind::kCommandTimedOut:
    case SimEvent::Kind::kFirstSliderCrossing:
    case SimEvent::Kind::kStepTooCoarse:
      ROS_WARN("kane_sim: %s (t = %.3f s)", text, event.time);
      break;
  }
}

}  // namespace kane_sim
