#include "kane_sim/teleop/key_decoder.h"

namespace kane_sim {
namespace {

constexpr char kEscape = 0x1b;

std::optional<Key> arrow(char final_byte) {
  switch (final_byte) {
    case 'A':
      return Key{Key::Code::kUp, 0};
    case 'B':
      return Key{Key::Code::kDown, 0};
    case 'C':
      return Key{Key::Code::kRight, 0};
    case 'D':
      return Key{Key::Code::kLeft, 0};
    default:
      return std::nullopt;
  }
}

}  // namespace

std::optional<Key> KeyDecoder::feed(char byte) {
  switch (stage_) {
    case Stage::kIdle:
      if (byte == kEscape) {
        stage_ = Stage::kEscape;
        return std::nullopt;
      }
      return Key::character(byte);
    case Stage::kEscape:
      if (byte == '[' || byte == 'O') {
        stage_ = Stage::kIntroducer;
        return std::nullopt;
      }
      stage_ = Stage::kIdle;
      return feed(byte);
    case Stage::kIntroducer:
      // CSI parameters (digits, ';') may precede the final byte, e.g. ESC [ 1 ; 5 C (Ctrl+Right).
      if ((byte >= '0' && byte <= '9') || byte == ';') return std::nullopt;
      stage_ = Stage::kIdle;
      return arrow(byte);
  }
  return std::nullopt;
}

}  // namespace kane_sim
