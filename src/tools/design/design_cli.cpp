#include "design/design_cli.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <vector>

#include "kane_sim/cli/number_argument.h"

namespace kane_sim {
namespace design_cli {

double number(const std::string& text, const std::string& flag) {
  try {
    return numberArgument(text, flag);
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
}

double angle(const std::string& text, const std::string& flag) {
  try {
    return angleArgument(text, flag);
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
}

std::pair<double, double> numberPair(const std::string& text, const std::string& flag) {
  const size_t comma = text.find(',');
  if (comma == std::string::npos || text.find(',', comma + 1) != std::string::npos)
    throw UsageError(flag + " takes two numbers A,B, got '" + text + "'");
  return {number(text.substr(0, comma), flag), number(text.substr(comma + 1), flag)};
}

namespace {

// Every weight named by its place when it is refused.
Eigen::Vector4d parseWeights(const std::string& text) {
  std::vector<std::string> items;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');) items.push_back(item);
  if (items.size() != 4 || text.empty() || text.back() == ',')
    throw UsageError("--Q takes 4 weights Q1,Q2,Q3,Q4 (the diagonal on q1, q2, u1, u2), got '" +
                     text + "'");
  Eigen::Vector4d values;
  const char* names[] = {"q1", "q2", "u1", "u2"};
  for (int i = 0; i < 4; ++i) {
    const std::string flag = std::string("--Q's weight on ") + names[i];
    values[i] = number(items[static_cast<size_t>(i)], flag);
    if (values[i] < 0)
      throw UsageError(flag + " must be >= 0, got '" + items[static_cast<size_t>(i)] + "'");
  }
  return values;
}

}  // namespace

LqrWeights weightsFrom(const boost::program_options::variables_map& vm, const Config& config,
                       const MechanismModel& model) {
  LqrWeights weights = defaultLqrWeights(config, model);
  if (vm.count("Q")) weights.Q = parseWeights(vm["Q"].as<std::string>()).asDiagonal();
  if (vm.count("R")) {
    weights.R = number(vm["R"].as<std::string>(), "--R");
    if (!(weights.R > 0)) throw UsageError("--R must be > 0, got " + vm["R"].as<std::string>());
  }
  return weights;
}

int writeOut(const boost::program_options::variables_map& vm, const std::string& config_path,
             const std::string& what, const std::function<void(std::ostream&)>& write) {
  const std::string path = vm["out"].as<std::string>();
  if (path == "-") {
    write(std::cout);
    return 0;
  }
  std::error_code same_error;
  if (!path.empty() && std::filesystem::equivalent(path, config_path, same_error)) {
    std::cerr << "design: --out " << path << " is the config itself: name another file\n";
    return kExitUsage;
  }
  std::ofstream out(path);
  write(out);
  if (!out.flush()) {
    std::cerr << "design: cannot write --out '" << path << "': " << std::strerror(errno) << "\n";
    return kExitOutput;
  }
  std::printf("\nWrote %s to %s\n", what.c_str(), path.c_str());
  return 0;
}

int flushStdout() {
  std::cout.flush();
  if (!std::cout || std::fflush(stdout) != 0) {
    std::cerr << "design: cannot write to stdout: " << std::strerror(errno) << "\n";
    return kExitOutput;
  }
  return 0;
}

}  // namespace design_cli
}  // namespace kane_sim
