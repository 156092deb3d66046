// Where a tool's CSV goes: a file staged as FILE.partial and renamed when complete, or stdout.
// One writer for simulate and scripts/sweep (through kane_sim._core.CsvOutput). A write that
// fails is an OutputError.
#ifndef KANE_SIM_CLI_STAGED_OUTPUT_H
#define KANE_SIM_CLI_STAGED_OUTPUT_H

#include <fstream>
#include <iostream>
#include <memory>
#include <ostream>
#include <stdexcept>
#include <string>

namespace kane_sim {
namespace cli {

struct OutputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// An output written under FILE.partial and renamed to FILE when complete (also when the run is
// interrupted or refused a step: what was simulated is kept): an existing FILE is replaced only
// by a finished one, and an interrupted run never leaves a truncated FILE behind. A FILE that
// exists and is not a regular file (/dev/stdout, a pipe) or is a link is written in place (a
// link keeps pointing where it did).
class StagedPath {
 public:
  explicit StagedPath(std::string path);
  StagedPath(const StagedPath&) = delete;
  StagedPath& operator=(const StagedPath&) = delete;
  ~StagedPath();  // not published: FILE.partial removed (an output error leaves no debris)
  const std::string& staging() const { return staging_; }
  void publish();  // FILE.partial -> FILE; throws OutputError

 private:
  std::string path_, staging_;
  bool published_ = false;
};

// The CSV: --csv FILE (staged, see StagedPath) or stdout (an empty path).
class CsvOutput {
 public:
  explicit CsvOutput(const std::string& path);  // throws OutputError naming --csv and the path
  std::ostream& stream() { return staged_ ? static_cast<std::ostream&>(file_) : std::cout; }
  // Flushed: what was written survives a crash (in FILE.partial). Throws OutputError.
  void flush();
  // The last bytes out and the file in place. Throws OutputError.
  void finish();

 private:
  std::unique_ptr<StagedPath> staged_;
  std::ofstream file_;
};

}  // namespace cli
}  // namespace kane_sim

#endif  // KANE_SIM_CLI_STAGED_OUTPUT_H
