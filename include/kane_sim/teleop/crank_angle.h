// The crank angle an orientation stands for: the crank turns about the mechanism frame's z
// axis, so a dragged interactive marker's orientation (in that frame) is read as its twist
// about z, and unwrapped next to the previous setpoint so dragging through +-pi keeps counting
// turns, as the continuous crank_joint does.
#ifndef KANE_SIM_TELEOP_CRANK_ANGLE_H
#define KANE_SIM_TELEOP_CRANK_ANGLE_H

#include <optional>

namespace kane_sim {

// The twist about z of the rotation (w, x, y, z) (unnormalized is fine), in (-pi, pi];
// nullopt when it has none (w = z = 0: a half turn about an axis normal to z) or when a
// component is not finite.
std::optional<double> twistAboutZ(double w, double x, double y, double z);

// angle + 2 pi k for the k that puts it nearest to `reference` (within pi).
double unwrapNear(double angle, double reference);

}  // namespace kane_sim

#endif  // KANE_SIM_TELEOP_CRANK_ANGLE_H
