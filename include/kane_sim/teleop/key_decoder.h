// Turns the bytes a terminal sends into keys: printable characters as themselves, the arrow
// keys' escape sequences (ESC [ A..D, and ESC O A..D in application cursor mode) as arrows.
// ROS-free, so the key handling of teleop_key is unit-tested without a terminal.
#ifndef KANE_SIM_TELEOP_KEY_DECODER_H
#define KANE_SIM_TELEOP_KEY_DECODER_H

#include <optional>

namespace kane_sim {

struct Key {
  enum class Code { kChar, kLeft, kRight, kUp, kDown };
  Code code = Code::kChar;
  char ch = 0;  // kChar only

  static Key character(char c) { return Key{Code::kChar, c}; }
  bool operator==(const Key& other) const { return code == other.code && ch == other.ch; }
};

class KeyDecoder {
 public:
  // One byte in; a key out when the byte completes one. An escape sequence that is not an arrow
  // is dropped whole; a lone ESC followed by an ordinary byte gives that byte.
  std::optional<Key> feed(char byte);

 private:
  enum class Stage { kIdle, kEscape, kIntroducer };
  Stage stage_ = Stage::kIdle;
};

}  // namespace kane_sim

#endif  // KANE_SIM_TELEOP_KEY_DECODER_H
