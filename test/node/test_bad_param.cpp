// A bad parameter stops the node with a non-zero exit and a message naming it
// (test/node/bad_param.test puts the bad values on the parameter server).
#include <future>
#include <initializer_list>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "test_helpers.h"

namespace {

struct Outcome {
  int exit_code;
  std::string output;  // stdout and stderr
};

Outcome runCommand(const std::string& command) {
  const kane_sim::test::CommandResult r = kane_sim::test::runCommand(command);
  return {r.exit_code, r.out + r.err};
}

// The node binary itself (rosrun's lookup is checked by node_cli and the launch tests): each
// start here ends at the config check, so the cases run side by side.
Outcome runNode(const std::string& name) {
  return runCommand(std::string("timeout 30 ") + KANE_SIM_NODE_EXE + " __name:=" + name);
}

// Every command at once; their outcomes in the same order.
std::vector<Outcome> runAll(const std::vector<std::string>& commands) {
  std::vector<std::future<Outcome>> running;
  for (const std::string& c : commands)
    running.push_back(std::async(std::launch::async, runCommand, c));
  std::vector<Outcome> outcomes;
  for (auto& r : running) outcomes.push_back(r.get());
  return outcomes;
}

struct BadCase {
  const char* node;     // the node name, whose private namespace holds the bad values
  const char* message;  // what the fatal message must say
};

void expectEachStopsTheNode(std::initializer_list<BadCase> cases) {
  std::vector<std::string> commands;
  for (const BadCase& c : cases)
    commands.push_back(std::string("timeout 30 ") + KANE_SIM_NODE_EXE + " __name:=" + c.node);
  const std::vector<Outcome> outcomes = runAll(commands);
  size_t i = 0;
  for (const BadCase& c : cases) {
    const Outcome& out = outcomes[i++];
    EXPECT_EQ(out.exit_code, 1) << c.node << ": " << out.output;
    EXPECT_NE(out.output.find(c.message), std::string::npos) << c.node << ": " << out.output;
  }
}

TEST(BadParam, NegativeMassStopsTheNodeNamingIt) {
  const Outcome out = runNode("negative_mass");
  EXPECT_EQ(out.exit_code, 1) << out.output;
  EXPECT_NE(out.output.find("/negative_mass/mechanism/rod_mass"), std::string::npos) << out.output;
  EXPECT_NE(out.output.find("must be > 0, got -1"), std::string::npos) << out.output;
}

TEST(BadParam, WrongTypeStopsTheNodeNamingIt) {
  const Outcome out = runNode("wrong_type");
  EXPECT_EQ(out.exit_code, 1) << out.output;
  EXPECT_NE(out.output.find("simulation/physics_rate"), std::string::npos) << out.output;
  EXPECT_NE(out.output.find("must be a number, got 'fast'"), std::string::npos) << out.output;
}

TEST(BadParam, PublishRateAbovePhysicsRateStopsTheNode) {
  const Outcome out = runNode("fast_publish");
  EXPECT_EQ(out.exit_code, 1) << out.output;
  EXPECT_NE(out.output.find("simulation/publish_rate"), std::string::npos) << out.output;
}

TEST(BadParam, ListWhereAMapBelongsUnknownIntegratorBadFrameName) {
  expectEachStopsTheNode({
      {"list_section", "config key 'simulation' must be a map, got a list"},
      {"bad_integrator", "unknown integrator 'euler' (valid: rk4, dopri5)"},
      {"bad_frame", "frames.prefix' must hold only letters, digits, '_' and '/', got 'robot 1'"},
  });
}

// Configurations that used to freeze the node (a `step` of 1e9 physics steps, a publish period
// that never comes), abort it (sim time past ROS's stamp range within minutes) or let it
// diverge in milliseconds (rk4 on a 43 000 rad/s mode) stop it at start-up instead.
TEST(BadParam, AbsurdRatesAndStiffnessStopTheNodeNamingTheLimit) {
  expectEachStopsTheNode({
      {"tiny_publish",
       "simulation/publish_rate: config key 'simulation.publish_rate' must be in "
       "[0.01, 1000] Hz, got 1e-300"},
      {"huge_ratio", "simulation.publish_rate' must be in [10, 1e+06] Hz, got 0.001"},
      {"slow_clock", "simulation.physics_rate' must be in [1, 1e+06] Hz"},
      {"tiny_factor", "simulation.real_time_factor' must be in [0.001, 1e+06]"},
      {"stiff_spring", "use simulation.integrator dopri5 or a physics_rate of at least 18400 Hz"},
      {"tiny_rod_mass", "gives equations of motion that are not finite"},
  });
}

// A flat private parameter (dynamic_reconfigure's name) is not read as the config key: said.
TEST(BadParam, AFlatPrivateParameterIsNamedAsNotRead) {
  const Outcome out = runNode("flat_param");
  EXPECT_NE(out.output.find("private parameter ~spring_stiffness = 400 is not read: the config "
                            "key is ~mechanism/spring_stiffness"),
            std::string::npos)
      << out.output;
}

TEST(BadParam, NoParametersAtAllSaysWhatToLoad) {
  const Outcome out = runNode("no_params");
  EXPECT_EQ(out.exit_code, 1) << out.output;
  EXPECT_NE(out.output.find("config/mechanism.yaml"), std::string::npos) << out.output;
}

// The small nodes' numeric private parameters (kane_sim/ros/node_params.h): not a number, not
// finite or out of range stops them with exit 1 naming the parameter and the value.
TEST(BadParam, SmallNodesRefuseBadNumbersNamingThem) {
  struct Case {
    const char* command;
    const char* message;
  };
  const Case cases[] = {
      {"pd_controller __name:=pd_bad _kp:=-1", "parameter /pd_bad/kp must be finite and >= 0"},
      {"pd_controller __name:=pd_text _setpoint:=left",
       "parameter /pd_text/setpoint must be a number"},
      {"crank_marker __name:=marker_bad _scale:=0",
       "parameter /marker_bad/scale must be finite and > 0"},
      {"teleop_key __name:=teleop_bad _repeat_rate:=fast",
       "parameter /teleop_bad/repeat_rate must be a number"},
      // A kHz bound on the repeats (1e9 flooded 648 000 messages in 6 s); numbers in their
      // shortest form (1e200 printed 200 digits, NaN printed -nan).
      {"teleop_key __name:=teleop_flood _repeat_rate:=1e9",
       "parameter /teleop_flood/repeat_rate must be in (0, 1000] Hz, got 1e+09"},
      {"pd_controller __name:=pd_huge _kp:=-1e200",
       "parameter /pd_huge/kp must be finite and >= 0, got -1e+200"},
      {"crank_marker __name:=marker_neg _scale:=-1e300",
       "parameter /marker_neg/scale must be finite and > 0, got -1e+300"},
      // The example controller's integral gain and its lockstep switch (a typo is not false).
      {"pd_controller __name:=pd_ki _ki:=-5", "parameter /pd_ki/ki must be finite and >= 0"},
      {"pd_controller __name:=pd_stamped _stamped:=yes",
       "parameter /pd_stamped/stamped must be true or false"},
      // The example controller's setpoint table: a device, no file, a file that is no table,
      // and a table beside a state feedback (which has no setpoint).
      {"pd_controller __name:=pd_table_zero _setpoint_table:=/dev/zero",
       "~setpoint_table: setpoint CSV '/dev/zero' is not a readable file (not a regular file"},
      {"pd_controller __name:=pd_table_none _setpoint_table:=/nonexistent/sp.csv",
       "~setpoint_table: setpoint CSV '/nonexistent/sp.csv'"},
      {"pd_controller __name:=pd_table_yaml _setpoint_table:=" KANE_SIM_CONFIG_DIR
       "/mechanism.yaml",
       "~setpoint_table: " KANE_SIM_CONFIG_DIR "/mechanism.yaml:"},
      // A torque's table (its header says so), a number where a path goes, a relative path
      // (said where it is read from), a setpoint beyond a million turns.
      {"pd_controller __name:=pd_table_torque _setpoint_table:=" KANE_SIM_CONFIG_DIR
       "/swing_up_plan.csv",
       "names a torque [N m], not a setpoint [rad]"},
      {"pd_controller __name:=pd_table_number _setpoint_table:=5",
       "parameter /pd_table_number/setpoint_table must be a file path, got 5"},
      {"pd_controller __name:=pd_table_relative _setpoint_table:=sp.csv",
       "a relative path is read from this node's working folder"},
      {"pd_controller __name:=pd_far _setpoint:=1e308",
       "parameter /pd_far/setpoint 1e+308 rad is beyond a million turns"},
      {"pd_controller __name:=pd_table_law _law:=" KANE_SIM_CONFIG_DIR
       "/upright_lqr.yaml _setpoint_table:=" KANE_SIM_CONFIG_DIR "/swing_up_plan.csv",
       "~setpoint_table plays the PD's setpoint, and ~law"},
      // The tracking controller: no plan, a device, a plan for another mechanism, a bad clamp.
      {"tracking_controller __name:=track_none", "parameter /track_none/plan must name a plan CSV"},
      {"tracking_controller __name:=track_zero _plan:=/dev/zero",
       "~plan: plan CSV '/dev/zero' is not a readable file (not a regular file"},
      {"tracking_controller __name:=track_other _plan:=" KANE_SIM_CONFIG_DIR
       "/swing_up_plan.csv _config:=" KANE_SIM_CONFIG_DIR "/mechanism.yaml",
       "initial_state.q1: the plan starts at 0, the config at 0.52"},
      {"tracking_controller __name:=track_limit _plan:=" KANE_SIM_CONFIG_DIR
       "/swing_up_plan.csv _torque_limit:=-1e308",
       "parameter /track_limit/torque_limit must be finite and > 0, got -1e+308"},
      {"tracking_controller __name:=track_csv _plan:=" KANE_SIM_CONFIG_DIR "/mechanism.yaml",
       "expected the plan's header 't,q1,q2,u1,u2,M_m,K_q1,K_q2,K_u1,K_u2'"},
  };
  std::vector<std::string> commands;
  for (const Case& c : cases)
    commands.push_back(std::string("timeout 30 rosrun kane_sim ") + c.command + " </dev/null");
  const std::vector<Outcome> outcomes = runAll(commands);
  for (size_t i = 0; i < commands.size(); ++i) {
    EXPECT_EQ(outcomes[i].exit_code, 1) << commands[i] << ": " << outcomes[i].output;
    EXPECT_NE(outcomes[i].output.find(cases[i].message), std::string::npos)
        << commands[i] << ": " << outcomes[i].output;
  }
}

}  // namespace
