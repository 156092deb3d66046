// The plan CSV `design plan` writes, the tracking controller follows and `simulate --torque-csv`
// plays (its t and M_m columns):
//
//   # kane_sim plan: <how it was made>           comments: what a reader wants to know
//   # mechanism.rod_mass = 1                     the mechanism it was designed for, every
//   # ...                                        constant of the equations, to 17 digits
//   # spring_rest_length = 0.3                   (the spring's rest length, from initial_state)
//   # periodic = 1                               the crank's error within (-pi, pi]
//   t,q1,q2,u1,u2,M_m,K_q1,K_q2,K_u1,K_u2
//   0,...                                        rows every `step` seconds from t = 0
//   # end of plan: 602 rows                      so that a cut-off file is not taken for a plan
//
// ROS-free.
#ifndef KANE_SIM_DESIGN_PLAN_FILE_H
#define KANE_SIM_DESIGN_PLAN_FILE_H

#include <map>
#include <ostream>
#include <string>
#include <vector>

#include "kane_sim/config/config.h"
#include "kane_sim/design/plan.h"

namespace kane_sim {

// The columns, in order.
extern const char* const kPlanColumns;
// The most rows a plan may have: a file of them (~200 bytes a row) stays within the 64 MiB every
// table the tools read may have (config/input_file.h).
constexpr long kMaxPlanRows = 300000;

struct PlanFile {
  Plan plan;
  // "mechanism.rod_mass" -> 1, ..., "spring_rest_length" -> 0.3: the mechanism it is for.
  std::map<std::string, double> mechanism;
};

// What a plan is for: every constant of the equations of `config` and the spring's rest length.
std::map<std::string, double> planMechanism(const Config& config);

// `notes`: comment lines (without '#') written first.
void writePlanCsv(std::ostream& out, const Plan& plan, const Config& config,
                  const std::vector<std::string>& notes);

// Throws PlanError naming the file, the line and the value: not a plan's header, a row of
// another length, a value not finite, times that do not start at 0 or are not evenly spaced (a
// gap) or closer than 1 µs, fewer than 2 rows, no end line or one that counts other rows (a
// file cut off). A regular file of at most 64 MiB.
PlanFile readPlanCsv(const std::string& path);

// Whether `path` holds a plan (its header line names the plan's columns); false when it cannot be
// read (the reader then says why).
bool isPlanCsv(const std::string& path);

// "" when the plan was designed for `config`'s mechanism and starts at its initial state; else
// which differs, both values, in words ("mechanism.rod_mass: the plan was designed for 1, the
// config has 1.2").
std::string planMismatch(const PlanFile& file, const Config& config);

}  // namespace kane_sim

#endif  // KANE_SIM_DESIGN_PLAN_FILE_H
