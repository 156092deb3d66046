// Driving by hand: the crank's interactive marker (test/node/crank_marker.test) and the
// keyboard teleop under a pseudo-terminal (test/node/teleop.test).
#include <fcntl.h>
#include <pty.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <mutex>
#include <string>
#include <thread>

#include <gtest/gtest.h>
#include <std_msgs/Float64.h>
#include <visualization_msgs/InteractiveMarkerFeedback.h>
#include <visualization_msgs/InteractiveMarkerInit.h>
#include <visualization_msgs/InteractiveMarkerUpdate.h>

#include "kane_sim/MechanismState.h"
#include "node_test_utils.h"

namespace kane_sim {
namespace {

using test::Recorder;

double twistAngle(const geometry_msgs::Quaternion& q) { return 2.0 * std::atan2(q.z, q.w); }

// ---- The interactive marker ------------------------------------------------------------------

class CrankMarker : public ::testing::Test {
 protected:
  void SetUp() override {
    feedback_ = test::connectedPublisher<visualization_msgs::InteractiveMarkerFeedback>(
        nh_, "crank_marker/feedback");
    ASSERT_GT(feedback_.getNumSubscribers(), 0u) << "crank_marker is not listening";
  }

  // What rviz sends while the ring is dragged: the marker's pose in its frame.
  void drag(double angle, const std::string& frame = "mechanism") {
    visualization_msgs::InteractiveMarkerFeedback feedback;
    feedback.header.frame_id = frame;
    feedback.client_id = "/rviz/InteractiveMarkers";
    feedback.marker_name = "crank";
    feedback.control_name = "rotate_crank";
    feedback.event_type = visualization_msgs::InteractiveMarkerFeedback::POSE_UPDATE;
    feedback.pose.orientation.w = std::cos(angle / 2);
    feedback.pose.orientation.z = std::sin(angle / 2);
    feedback_.publish(feedback);
  }

  // A drag as rviz sends it: pose updates repeated while the ring is held (every 0.2 s here), so
  // a setpoint published before this test's subscriber was connected is published again.
  bool dragUntilSetpoint(double angle, double expected, double timeout_s) {
    const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(timeout_s);
    while (ros::WallTime::now() < end) {
      drag(angle);
      if (test::waitFor([&] { return setpointIs(expected); }, 0.2)) return true;
    }
    return false;
  }
  bool setpointIs(double value) const {
    return setpoints_.count() > 0 && std::abs(setpoints_.last().data - value) < 1e-9;
  }

  ros::NodeHandle nh_;
  ros::Publisher feedback_;
  Recorder<std_msgs::Float64> setpoints_{nh_, "setpoint"};
  Recorder<MechanismState> state_{nh_, "mechanism_state"};
};

// crank_marker.test gives pd_controller the setpoint 0.3: the marker shows it from the start.
TEST_F(CrankMarker, StartsAtTheControllersSetpoint) {
  Recorder<visualization_msgs::InteractiveMarkerInit> init(nh_, "crank_marker/update_full");
  ASSERT_TRUE(init.waitForCount(1, 10.0));
  ASSERT_EQ(init.last().markers.size(), 1u);
  EXPECT_EQ(init.last().markers[0].header.frame_id, "mechanism");
  EXPECT_NEAR(twistAngle(init.last().markers[0].pose.orientation), 0.3, 1e-9);
}

// Dragging the ring publishes its angle as the setpoint, and the PD controller takes the crank
// there (0.05 rad: the controller test's tolerance, a PD's steady error is <= 0.03 rad here).
TEST_F(CrankMarker, DraggingTheRingMovesTheSetpointAndTheCrank) {
  ASSERT_TRUE(state_.waitForCount(1, 15.0));
  ASSERT_TRUE(dragUntilSetpoint(0.8, 0.8, 5.0)) << "no setpoint 0.8 after the drag";
  test::sleepWall(3.0);
  EXPECT_NEAR(state_.last().q[0], 0.8, 0.05);
}

// Through +-pi the setpoint keeps counting turns (the crank joint is continuous): 2.5, 3.0,
// then the marker's -3.0 is 2 pi - 3.0, not a turn back the long way.
TEST_F(CrankMarker, DraggingThroughPiKeepsCountingTurns) {
  for (const double angle : {1.5, 2.5, 3.0})
    ASSERT_TRUE(dragUntilSetpoint(angle, angle, 5.0)) << angle;
  EXPECT_TRUE(dragUntilSetpoint(-3.0, 2 * M_PI - 3.0, 5.0))
      << "last setpoint " << setpoints_.last().data;
  // a jump of 2.78 rad (< pi) back: taken as it is
  EXPECT_TRUE(dragUntilSetpoint(0.5, 0.5, 5.0)) << "last setpoint " << setpoints_.last().data;
}

TEST_F(CrankMarker, FeedbackInAnotherFrameIsIgnored) {
  ASSERT_TRUE(dragUntilSetpoint(0.6, 0.6, 5.0));
  setpoints_.clear();
  drag(1.2, "world");
  test::sleepWall(1.0);
  EXPECT_EQ(setpoints_.count(), 0u) << "a setpoint from feedback in frame world";
}

// A setpoint from anyone else (teleop_key, a script) moves the marker in rviz.
TEST_F(CrankMarker, ASetpointFromAnotherNodeMovesTheMarker) {
  Recorder<visualization_msgs::InteractiveMarkerUpdate> updates(nh_, "crank_marker/update");
  ros::Publisher setpoint = test::connectedPublisher<std_msgs::Float64>(nh_, "setpoint");
  test::sleepWall(0.5);
  test::send(setpoint, -0.4);
  EXPECT_TRUE(test::waitFor(
      [&] {
        for (const auto& update : updates.messages())
          for (const auto& pose : update.poses)
            if (pose.name == "crank" && std::abs(twistAngle(pose.pose.orientation) + 0.4) < 1e-9)
              return true;
        return false;
      },
      5.0))
      << "the marker did not move to -0.4";
}

// ---- The keyboard teleop -----------------------------------------------------------------------

// teleop_key on a pseudo-terminal, as a user's terminal would run it: keys written to the
// master side arrive as keystrokes; what it prints is collected.
class PtyProcess {
 public:
  explicit PtyProcess(const std::string& node_name) {
    pid_ = forkpty(&master_, nullptr, nullptr, nullptr);
    if (pid_ == 0) {
      const std::string name_arg = "__name:=" + node_name;
      execl(KANE_SIM_TELEOP_EXE, "teleop_key", name_arg.c_str(), static_cast<char*>(nullptr));
      _exit(127);
    }
    reader_ = std::thread([this] {
      char buffer[256];
      for (;;) {
        const ssize_t n = ::read(master_, buffer, sizeof buffer);
        if (n <= 0) break;  // EIO once the child has gone
        std::lock_guard<std::mutex> lock(mutex_);
        output_.append(buffer, static_cast<size_t>(n));
      }
    });
  }
  ~PtyProcess() {
    if (pid_ > 0 && !exited_) {
      kill(pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
    }
    close(master_);
    reader_.join();
  }
  bool started() const { return pid_ > 0; }
  void type(const std::string& keys) {
    ASSERT_EQ(::write(master_, keys.data(), keys.size()), static_cast<ssize_t>(keys.size()));
  }
  std::string output() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return output_;
  }
  bool printed(const std::string& text, double timeout_s) const {
    return test::waitFor([&] { return output().find(text) != std::string::npos; }, timeout_s);
  }
  void signal(int sig) { kill(pid_, sig); }
  // The exit status, or -1 when it has not exited within timeout_s.
  int waitExit(double timeout_s) {
    int status = 0;
    const bool done =
        test::waitFor([&] { return waitpid(pid_, &status, WNOHANG) == pid_; }, timeout_s);
    if (!done) return -1;
    exited_ = true;
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  }

 private:
  pid_t pid_ = -1;
  int master_ = -1;
  bool exited_ = false;
  std::thread reader_;
  mutable std::mutex mutex_;
  std::string output_;
};

class Teleop : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_TRUE(state_.waitForCount(1, 15.0)); }

  bool waitForTorque(double value, double timeout_s) {
    return test::waitFor([&] { return torques_.count() > 0 && torques_.last().data == value; },
                         timeout_s);
  }

  ros::NodeHandle nh_;
  Recorder<std_msgs::Float64> torques_{nh_, "torque_command"};
  Recorder<std_msgs::Float64> setpoints_{nh_, "setpoint"};
  Recorder<MechanismState> state_{nh_, "mechanism_state"};
};

// Right arrow and 'd' step the torque by 0.5 N m, left arrow back; the torque is held beyond
// the sim's command timeout (0.5 s) because teleop_key repeats it; q quits with torque 0.
TEST_F(Teleop, KeysStepTheTorqueWhichHoldsUntilQuit) {
  PtyProcess teleop("teleop_key_torque");
  ASSERT_TRUE(teleop.started());
  ASSERT_TRUE(teleop.printed("torque mode: torque +0.000 N m", 10.0)) << teleop.output();
  ASSERT_TRUE(test::waitFor([&] { return torques_.connected(); }, 10.0));
  teleop.type("\x1b[C\x1b[Cd");
  ASSERT_TRUE(waitForTorque(1.5, 5.0)) << teleop.output();
  EXPECT_TRUE(teleop.printed("torque +1.500 N m", 5.0));
  teleop.type("\x1b[D");
  ASSERT_TRUE(waitForTorque(1.0, 5.0));
  const size_t before = torques_.count();
  test::sleepWall(1.5);  // three command timeouts
  EXPECT_EQ(state_.last().applied_torque, 1.0) << "the torque lapsed while the key held it";
  // 30 repeats at 20 Hz; 20 leaves room for a loaded machine, 0.5 s gaps would give <= 3.
  EXPECT_GE(torques_.count() - before, 20u);

  teleop.type("q");
  EXPECT_EQ(teleop.waitExit(5.0), 0) << teleop.output();
  EXPECT_TRUE(waitForTorque(0.0, 2.0)) << "no torque 0 when quitting";
  test::sleepWall(0.3);
  EXPECT_EQ(state_.last().applied_torque, 0.0);
}

// p switches to setpoint mode at the crank's angle; the arrows then step the setpoint by 0.1 rad.
TEST_F(Teleop, SetpointModeStepsTheSetpointFromTheCrankAngle) {
  PtyProcess teleop("teleop_key_setpoint");
  ASSERT_TRUE(teleop.printed("torque mode", 10.0)) << teleop.output();
  ASSERT_TRUE(test::waitFor([&] { return setpoints_.connected(); }, 10.0));
  test::sleepWall(0.5);  // joint_states reach it
  teleop.type("p");
  ASSERT_TRUE(setpoints_.waitForCount(1, 5.0)) << teleop.output();
  const double start = setpoints_.last().data;
  EXPECT_NEAR(start, state_.last().q[0], 0.5) << "setpoint mode starts near the crank angle";
  teleop.type("\x1b[C\x1b[C");
  ASSERT_TRUE(setpoints_.waitForCount(3, 5.0));
  EXPECT_NEAR(setpoints_.last().data, start + 0.2, 1e-12);
  teleop.type("\x1b[A\x1b[D");  // step x 2, then one step down
  ASSERT_TRUE(setpoints_.waitForCount(4, 5.0));
  EXPECT_NEAR(setpoints_.last().data, start, 1e-12);
  EXPECT_TRUE(teleop.printed("setpoint mode: setpoint", 5.0));
  teleop.signal(SIGINT);  // Ctrl-C
  EXPECT_EQ(teleop.waitExit(5.0), 0) << teleop.output();
}

// Ctrl-C in torque mode also leaves the crank unpowered.
TEST_F(Teleop, InterruptCommandsTorqueZeroFirst) {
  PtyProcess teleop("teleop_key_interrupt");
  ASSERT_TRUE(teleop.printed("torque mode", 10.0)) << teleop.output();
  ASSERT_TRUE(test::waitFor([&] { return torques_.connected(); }, 10.0));
  teleop.type("ddd");
  ASSERT_TRUE(waitForTorque(1.5, 5.0));
  teleop.signal(SIGINT);
  EXPECT_EQ(teleop.waitExit(5.0), 0) << teleop.output();
  EXPECT_TRUE(waitForTorque(0.0, 2.0)) << "no torque 0 after Ctrl-C";
}

}  // namespace
}  // namespace kane_sim
