#include "keyboard_input.h"

#include <poll.h>
#include <unistd.h>

#include <cerrno>

namespace kane_sim {

KeyboardInput::KeyboardInput(int fd) : fd_(fd) {
  termios settings;
  if (!isatty(fd_) || tcgetattr(fd_, &settings) != 0) return;
  saved_ = settings;
  settings.c_lflag &= ~static_cast<tcflag_t>(ICANON | ECHO);  // every key at once, unechoed
  settings.c_cc[VMIN] = 1;
  settings.c_cc[VTIME] = 0;
  tcsetattr(fd_, TCSANOW, &settings);
}

KeyboardInput::~KeyboardInput() {
  if (saved_) tcsetattr(fd_, TCSANOW, &*saved_);
}

std::optional<std::string> KeyboardInput::read(double timeout_s) {
  pollfd ready{fd_, POLLIN, 0};
  const int n = poll(&ready, 1, static_cast<int>(timeout_s * 1000.0));
  if (n < 0) return errno == EINTR ? std::optional<std::string>("") : std::nullopt;
  if (n == 0) return std::string();
  char buffer[64];
  const ssize_t got = ::read(fd_, buffer, sizeof buffer);
  if (got < 0)
    return errno == EINTR || errno == EAGAIN ? std::optional<std::string>("") : std::nullopt;
  if (got == 0) return std::nullopt;  // end of input (pipe closed, terminal hung up)
  return std::string(buffer, static_cast<size_t>(got));
}

}  // namespace kane_sim
