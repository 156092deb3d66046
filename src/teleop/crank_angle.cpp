#include "kane_sim/teleop/crank_angle.h"

#include <algorithm>
#include <cmath>

namespace kane_sim {

std::optional<double> twistAboutZ(double w, double x, double y, double z) {
  if (!std::isfinite(w) || !std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
    return std::nullopt;
  // Swing-twist decomposition: the twist about z is the quaternion (w, 0, 0, z), normalized.
  // Its angle 2 atan2(z, w) lies in (-2 pi, 2 pi]; fold it into (-pi, pi].
  // Scaled by the largest component first, so a valid but huge (1e200) or tiny quaternion
  // neither overflows nor underflows.
  const double scale = std::max({std::abs(w), std::abs(x), std::abs(y), std::abs(z)});
  if (scale == 0.0) return std::nullopt;
  w /= scale;
  x /= scale;
  y /= scale;
  z /= scale;
  const double norm = std::hypot(w, z);
  if (norm < 1e-12 * std::sqrt(w * w + x * x + y * y + z * z) || norm == 0.0) return std::nullopt;
  return std::remainder(2.0 * std::atan2(z, w), 2.0 * M_PI);
}

double unwrapNear(double angle, double reference) {
  return reference + std::remainder(angle - reference, 2.0 * M_PI);
}

}  // namespace kane_sim
