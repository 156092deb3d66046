// Opening a file a user names (a config, a torque CSV, a sweep file): only a regular file, and
// only up to a size that says what the file is for. /dev/zero, a FIFO or a 36 MB "config" would
// otherwise be read until memory runs out before anything could say what is wrong.
#ifndef KANE_SIM_CONFIG_INPUT_FILE_H
#define KANE_SIM_CONFIG_INPUT_FILE_H

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

namespace kane_sim {

// Largest inputs [bytes]: a config is ~4 KB (1 MiB leaves room for comments); a torque table or
// a sweep file of 64 MiB holds ~3 million rows.
constexpr std::uintmax_t kMaxConfigBytes = 1u << 20;
constexpr std::uintmax_t kMaxTableBytes = 64u << 20;

// Throws std::invalid_argument "<what> '<path>' ..." when `path` is not a regular file, is larger
// than `max_bytes` or cannot be opened.
inline std::ifstream openInputFile(const std::string& path, const std::string& what,
                                   std::uintmax_t max_bytes) {
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error))
    throw std::invalid_argument(what + " '" + path + "' is not a readable file" +
                                (std::filesystem::exists(path, error)
                                     ? " (not a regular file: a device, a pipe or a folder)"
                                     : " (no such file)"));
  const std::uintmax_t size = std::filesystem::file_size(path, error);
  if (!error && size > max_bytes)
    throw std::invalid_argument(what + " '" + path + "' has " + std::to_string(size) +
                                " bytes, more than the " + std::to_string(max_bytes) + " a " +
                                what + " may have");
  std::ifstream in(path);
  if (!in) throw std::invalid_argument(what + " '" + path + "' cannot be opened");
  return in;
}

}  // namespace kane_sim

#endif  // KANE_SIM_CONFIG_INPUT_FILE_H
