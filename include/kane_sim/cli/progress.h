// A progress line for long work (a long simulate run, a sweep), on stderr and only when stderr
// is a terminal: "simulate: 42.0 % (126000 of 300000 s), 16 s left", rewritten in place at most
// four times a second and erased when the work ends. Not a terminal (a pipe, a log file, a test):
// nothing at all, so CSV on stdout and logs stay clean.
#ifndef KANE_SIM_CLI_PROGRESS_H
#define KANE_SIM_CLI_PROGRESS_H

#include <chrono>
#include <cstdint>
#include <ostream>
#include <string>

namespace kane_sim {
namespace cli {

class Progress {
 public:
  // what: the tool ("simulate"); total: the work in `unit` ("s", "cases"); shown: whether to
  // draw at all (by default: stderr is a terminal).
  Progress(std::ostream& out, std::string what, double total, std::string unit, bool shown);
  Progress(std::string what, double total, std::string unit);
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;
  ~Progress() { finish(); }

  // `done` of the total so far: cheap enough to call at every output row (the clock is read
  // every 64th call; the first call draws at once, so a run shows that it started).
  void update(double done);
  // Erases the line, so that a message printed now starts on a clean line (the next update
  // draws it again).
  void clear();
  // Erases the line for good: the work is over.
  void finish() {
    clear();
    shown_ = false;
  }

  bool shown() const { return shown_; }

 private:
  void draw(double done, std::chrono::steady_clock::time_point now);

  std::ostream& out_;
  std::string what_, unit_;
  double total_;
  bool shown_;
  bool drawn_ = false;
  std::uint64_t calls_ = 0;
  std::chrono::steady_clock::time_point start_, last_;
};

}  // namespace cli
}  // namespace kane_sim

#endif  // KANE_SIM_CLI_PROGRESS_H
