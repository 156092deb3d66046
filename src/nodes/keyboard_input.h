// The keyboard as teleop_key reads it: stdin switched to non-canonical, no-echo mode while the
// object lives (Ctrl-C still raises SIGINT, as in turtle_teleop_key), restored on destruction.
// When stdin is not a terminal (a pipe, a file) the bytes are read as they come.
#ifndef KANE_SIM_NODES_KEYBOARD_INPUT_H
#define KANE_SIM_NODES_KEYBOARD_INPUT_H

#include <termios.h>

#include <optional>
#include <string>

namespace kane_sim {

class KeyboardInput {
 public:
  explicit KeyboardInput(int fd);
  ~KeyboardInput();
  KeyboardInput(const KeyboardInput&) = delete;
  KeyboardInput& operator=(const KeyboardInput&) = delete;

  bool isTerminal() const { return saved_.has_value(); }
  // The bytes available within timeout_s (empty when none came); nullopt at end of input.
  std::optional<std::string> read(double timeout_s);

 private:
  int fd_;
  std::optional<termios> saved_;
};

}  // namespace kane_sim

#endif  // KANE_SIM_NODES_KEYBOARD_INPUT_H
