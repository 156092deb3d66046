// Shared by every test executable: the shipped config files through the real loader, the CSV
// that `simulate` writes, and running a command as a user would.
#ifndef KANE_SIM_TEST_COMMON_TEST_HELPERS_H
#define KANE_SIM_TEST_COMMON_TEST_HELPERS_H

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "kane_sim/config/load_config.h"

namespace kane_sim {
namespace test {

inline std::string configPath(const std::string& file) {
  return std::string(KANE_SIM_CONFIG_DIR) + "/" + file;
}
// The text of a doc page between its "<!-- generated: COMMAND ... -->" line and "<!-- end of
// generated table -->" (throws when either is missing): what a test compares with the code
// that generates it.
inline std::string generatedDocSection(const std::string& page, const std::string& command) {
  std::ifstream file(std::string(KANE_SIM_CONFIG_DIR) + "/../" + page);
  if (!file) throw std::runtime_error(page + " not found beside config/");
  std::stringstream doc;
  doc << file.rdbuf();
  const std::string text = doc.str();
  const std::size_t a = text.find("<!-- generated: " + command);
  if (a == std::string::npos) throw std::runtime_error(page + ": no generated: " + command);
  const std::size_t table = text.find('\n', a) + 1;
  const std::size_t b = text.find("<!-- end of generated table -->", table);
  if (b == std::string::npos) throw std::runtime_error(page + ": no end of generated table");
  return text.substr(table, b - table);
}

inline Config defaultConfig() { return loadConfigFile(configPath("mechanism.yaml")).config; }
inline Config textbookConfig() { return loadConfigFile(configPath("textbook.yaml")).config; }

// The rows of a CSV written by `simulate` (header returned separately).
inline std::vector<std::vector<double>> parseCsv(const std::string& text, std::string* header) {
  std::istringstream in(text);
  std::getline(in, *header);
  std::vector<std::vector<double>> rows;
  std::string line;
  while (std::getline(in, line)) {
    std::vector<double> row;
    std::istringstream fields(line);
    std::string field;
    while (std::getline(fields, field, ',')) row.push_back(std::stod(field));
    rows.push_back(row);
  }
  return rows;
}

// The link frame each marker lives in (unprefixed): pin O and the rail in `mechanism`, pin A
// and the torque arrow on rod 1, pin B and the spring on slider 3 (src/ros/markers.cpp).
inline std::string markerFrame(const std::string& ns, int id) {
  if (ns == "pins") return id == 0 ? "mechanism" : id == 1 ? "rod1" : "slider3";
  if (ns == "torque") return "rod1";
  if (ns == "spring") return "slider3";
  return "mechanism";
}

struct CommandResult {
  int exit_code = -1;  // -1 when killed by a signal
  std::string out;     // stdout
  std::string err;     // stderr
};

// Runs `command` with /bin/sh, capturing stdout and stderr apart.
inline CommandResult runCommand(const std::string& command) {
  char err_path[] = "/tmp/kane_sim_test_stderr_XXXXXX";
  const int fd = mkstemp(err_path);
  if (fd >= 0) close(fd);
  CommandResult result;
  FILE* pipe = popen((command + " 2>" + err_path).c_str(), "r");
  if (!pipe) return result;
  char buffer[4096];
  size_t n;
  while ((n = fread(buffer, 1, sizeof(buffer), pipe)) > 0) result.out.append(buffer, n);
  const int status = pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream err(err_path);
  result.err.assign(std::istreambuf_iterator<char>(err), {});
  std::remove(err_path);
  return result;
}

}  // namespace test
}  // namespace kane_sim

#endif  // KANE_SIM_TEST_COMMON_TEST_HELPERS_H
