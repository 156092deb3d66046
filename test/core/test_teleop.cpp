// Driving by hand, without a terminal or rviz: the bytes a terminal sends become keys, keys
// become torque and setpoint commands, a dragged orientation becomes a crank angle.
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "kane_sim/format_number.h"
#include "kane_sim/teleop/crank_angle.h"
#include "kane_sim/teleop/key_decoder.h"
#include "kane_sim/teleop/key_teleop.h"

namespace kane_sim {
namespace {

std::vector<Key> decode(const std::string& bytes) {
  KeyDecoder decoder;
  std::vector<Key> keys;
  for (const char b : bytes)
    if (const auto key = decoder.feed(b)) keys.push_back(*key);
  return keys;
}

const Key kRight{Key::Code::kRight, 0};
const Key kLeft{Key::Code::kLeft, 0};
const Key kUp{Key::Code::kUp, 0};
const Key kDown{Key::Code::kDown, 0};

TEST(KeyDecoder, ArrowEscapeSequencesAndCharacters) {
  // Normal (ESC [) and application (ESC O) cursor modes, a CSI with parameters (Ctrl+Right).
  const std::vector<Key> keys = decode("\x1b[A\x1b[B\x1b[C\x1b[Dd\x1bOC\x1b[1;5Dq");
  const std::vector<Key> expected = {
      kUp, kDown, kRight, kLeft, Key::character('d'), kRight, kLeft, Key::character('q')};
  EXPECT_EQ(keys, expected);
}

TEST(KeyDecoder, OtherEscapeSequencesAreDroppedWhole) {
  // F5 (ESC [ 1 5 ~) and Home (ESC [ H) are no arrows; ESC then 'a' is Alt+a: gives 'a'.
  const std::vector<Key> keys = decode(
      "\x1b[15~\x1b[Hx\x1b"
      "a");
  const std::vector<Key> expected = {Key::character('x'), Key::character('a')};
  EXPECT_EQ(keys, expected);
}

TEST(KeyDecoder, SequencesSplitAcrossReadsStillDecode) {
  KeyDecoder decoder;
  EXPECT_FALSE(decoder.feed('\x1b'));
  EXPECT_FALSE(decoder.feed('['));
  const auto key = decoder.feed('C');
  ASSERT_TRUE(key);
  EXPECT_EQ(*key, kRight);
}

TEST(KeyTeleop, ArrowsAndLettersStepTheTorqueWithinItsLimit) {
  TeleopSettings settings;
  settings.torque_step = 0.5;
  settings.torque_limit = 2.0;
  KeyTeleop teleop(settings);
  EXPECT_EQ(teleop.mode(), TeleopMode::kTorque);
  EXPECT_EQ(teleop.press(kRight), TeleopEvent::kTorqueChanged);
  EXPECT_EQ(teleop.press(Key::character('d')), TeleopEvent::kTorqueChanged);
  EXPECT_DOUBLE_EQ(teleop.torque(), 1.0);
  EXPECT_EQ(teleop.press(kLeft), TeleopEvent::kTorqueChanged);
  EXPECT_DOUBLE_EQ(teleop.torque(), 0.5);
  for (int i = 0; i < 10; ++i) teleop.press(kRight);
  EXPECT_DOUBLE_EQ(teleop.torque(), 2.0);  // clamped at torque_limit
  EXPECT_EQ(teleop.press(Key::character(' ')), TeleopEvent::kTorqueChanged);
  EXPECT_DOUBLE_EQ(teleop.torque(), 0.0);
  for (int i = 0; i < 10; ++i) teleop.press(Key::character('a'));
  EXPECT_DOUBLE_EQ(teleop.torque(), -2.0);
  EXPECT_NE(teleop.status().find("torque -2.000 N m"), std::string::npos) << teleop.status();
}

TEST(KeyTeleop, StepDoublesAndHalvesWithinItsRange) {
  TeleopSettings settings;
  settings.torque_step = 0.5;
  settings.torque_limit = 3.0;
  KeyTeleop teleop(settings);
  EXPECT_EQ(teleop.press(kUp), TeleopEvent::kStepChanged);
  EXPECT_DOUBLE_EQ(teleop.torque(), 0.0);  // a step change commands nothing
  teleop.press(kRight);
  EXPECT_DOUBLE_EQ(teleop.torque(), 1.0);
  for (int i = 0; i < 10; ++i) teleop.press(Key::character('w'));
  teleop.press(kLeft);
  EXPECT_DOUBLE_EQ(teleop.torque(), -2.0);  // step capped at the limit (3): 1 - 3
  for (int i = 0; i < 20; ++i) teleop.press(kDown);
  teleop.press(Key::character(' '));
  teleop.press(kRight);
  EXPECT_DOUBLE_EQ(teleop.torque(), 0.5 / 64);  // never below 1/64 of the start
}

TEST(KeyTeleop, SetpointModeStartsAtTheCrankAndStepsTheSetpoint) {
  KeyTeleop teleop(TeleopSettings{});
  teleop.press(kRight);  // some torque first
  teleop.setCrankAngle(0.7);
  EXPECT_EQ(teleop.press(Key::character('p')), TeleopEvent::kModeChanged);
  EXPECT_EQ(teleop.mode(), TeleopMode::kSetpoint);
  EXPECT_DOUBLE_EQ(teleop.setpoint(), 0.7);
  EXPECT_EQ(teleop.press(Key::character('p')), TeleopEvent::kNone);  // already there
  EXPECT_EQ(teleop.press(kRight), TeleopEvent::kSetpointChanged);
  EXPECT_EQ(teleop.press(kRight), TeleopEvent::kSetpointChanged);
  EXPECT_NEAR(teleop.setpoint(), 0.9, 1e-15);
  EXPECT_NE(teleop.status().find("setpoint +0.900 rad"), std::string::npos) << teleop.status();
  // Back in torque mode the torque restarts from 0: the key that switched commands nothing.
  EXPECT_EQ(teleop.press(Key::character('t')), TeleopEvent::kModeChanged);
  EXPECT_DOUBLE_EQ(teleop.torque(), 0.0);
}

TEST(KeyTeleop, QuitHelpAndUnknownKeys) {
  KeyTeleop teleop(TeleopSettings{});
  EXPECT_EQ(teleop.press(Key::character('q')), TeleopEvent::kQuit);
  EXPECT_EQ(teleop.press(Key::character('h')), TeleopEvent::kHelp);
  EXPECT_EQ(teleop.press(Key::character('?')), TeleopEvent::kHelp);
  EXPECT_EQ(teleop.press(Key::character('z')), TeleopEvent::kNone);
  EXPECT_EQ(teleop.press(Key::character('\n')), TeleopEvent::kNone);
  EXPECT_DOUBLE_EQ(teleop.torque(), 0.0);
}

TEST(KeyTeleop, BadSettingsAreRefusedByName) {
  TeleopSettings settings;
  settings.torque_step = -1.0;
  try {
    KeyTeleop teleop(settings);
    FAIL() << "a negative step was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("torque_step must be finite and > 0, got -1"),
              std::string::npos)
        << e.what();
  }
  settings = TeleopSettings{};
  settings.setpoint_step = NAN;
  EXPECT_THROW(KeyTeleop{settings}, std::invalid_argument);
}

TEST(CrankAngle, TwistAboutZOfTurnsAboutZ) {
  for (double angle = -3.1; angle <= 3.1; angle += 0.1) {
    const auto twist = twistAboutZ(std::cos(angle / 2), 0, 0, std::sin(angle / 2));
    ASSERT_TRUE(twist);
    EXPECT_NEAR(*twist, angle, 1e-12);
    // -q is the same rotation; an unnormalized quaternion too.
    EXPECT_NEAR(*twistAboutZ(-3 * std::cos(angle / 2), 0, 0, -3 * std::sin(angle / 2)), angle,
                1e-12);
  }
}

TEST(CrankAngle, TwistIgnoresASwingAndRefusesWhatHasNoTwist) {
  // q = twist(0.4 about z) * swing(0.3 about x): the twist is still 0.4.
  const double t = 0.2, s = 0.15;  // half angles
  const double w = std::cos(t) * std::cos(s), x = std::cos(t) * std::sin(s),
               y = std::sin(t) * std::sin(s), z = std::sin(t) * std::cos(s);
  EXPECT_NEAR(*twistAboutZ(w, x, y, z), 0.4, 1e-12);
  EXPECT_FALSE(twistAboutZ(0, 1, 0, 0));  // half turn about x
  EXPECT_FALSE(twistAboutZ(0, 0, 0, 0));
  EXPECT_FALSE(twistAboutZ(NAN, 0, 0, 1));
}

TEST(CrankAngle, UnwrapKeepsCountingTurns) {
  EXPECT_NEAR(unwrapNear(-3.0, 3.0), 2 * M_PI - 3.0, 1e-12);  // dragged through +pi
  EXPECT_NEAR(unwrapNear(3.0, -3.0), 3.0 - 2 * M_PI, 1e-12);
  EXPECT_NEAR(unwrapNear(0.5, 4 * M_PI), 4 * M_PI + 0.5, 1e-12);
  EXPECT_NEAR(unwrapNear(0.5, 0.2), 0.5, 1e-15);
}

// A valid orientation with any scale: (1e200, 0, 0, 1e200) is a quarter turn; the plain norm
// overflowed to inf and the angle was ignored. Tiny scales likewise.
TEST(CrankAngle, ScaledQuaternionsKeepTheirAngle) {
  for (double scale : {1e-300, 1e-150, 1.0, 1e150, 1e300}) {
    const auto angle = twistAboutZ(scale * std::cos(0.25), 0.0, 0.0, scale * std::sin(0.25));
    ASSERT_TRUE(angle.has_value()) << scale;
    EXPECT_NEAR(*angle, 0.5, 1e-12) << scale;
  }
}

// Messages print numbers in their shortest exact form, NaN as "nan" whatever its sign bit.
TEST(FormatNumber, ShortestFormAndOneNan) {
  EXPECT_EQ(formatNumber(0.1), "0.1");
  EXPECT_EQ(formatNumber(-50.0), "-50");
  EXPECT_EQ(formatNumber(1e200), "1e+200");
  EXPECT_EQ(formatNumber(-std::nan("")), "nan");
  EXPECT_EQ(formatNumber(std::nan("")), "nan");
  EXPECT_EQ(formatNumber(-INFINITY), "-inf");
}

// Times in messages read as the grid's: a sim time summed step by step prints 19.99.
TEST(FormatNumber, TimesToTheNanosecond) {
  double t = 0.0;
  for (int i = 0; i < 1999; ++i) t += 0.01;
  ASSERT_NE(formatNumber(t), "19.99");  // the sum's own rounding shows
  EXPECT_EQ(formatTime(t), "19.99");
  EXPECT_EQ(formatTime(1e-9), "1e-09");
  EXPECT_EQ(formatTime(std::nan("")), "nan");
  EXPECT_EQ(formatTime(1e300), "1e+300");
}

}  // namespace
}  // namespace kane_sim
