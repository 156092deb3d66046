// Google Benchmark's console output plus, at the end, each benchmark's time as a ratio to a
// chosen baseline measured in the same run (ratios within one run are what survive a shared,
// noisy machine). With --benchmark_repetitions the median is used.
#ifndef KANE_SIM_BENCH_RATIO_REPORTER_H
#define KANE_SIM_BENCH_RATIO_REPORTER_H

#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

namespace kane_sim {
namespace bench {

class RatioReporter : public benchmark::ConsoleReporter {
 public:
  explicit RatioReporter(std::string baseline) : baseline_(std::move(baseline)) {}

  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& run : runs) {
      const bool median = run.run_type == Run::RT_Aggregate && run.aggregate_name == "median";
      const std::string name = run.run_name.str();
      if (median || (run.run_type == Run::RT_Iteration && !medians_.count(name))) {
        ns_per_item_[name] = run.GetAdjustedRealTime();  // in the benchmark's time unit
        unit_[name] = run.time_unit;
        if (median) medians_[name] = true;
      }
    }
    ConsoleReporter::ReportRuns(runs);
  }

  void Finalize() override {
    ConsoleReporter::Finalize();
    if (!ns_per_item_.count(baseline_)) return;
    const double base = nanoseconds(baseline_);
    std::printf("\n| benchmark | ns per call | ratio to %s |\n|---|---|---|\n", baseline_.c_str());
    for (const auto& [name, value] : ns_per_item_) {
      static_cast<void>(value);
      std::printf("| %s | %.1f | %.2f |\n", name.c_str(), nanoseconds(name),
                  nanoseconds(name) / base);
    }
  }

  double nanoseconds(const std::string& name) const {
    const double scale = unit_.at(name) == benchmark::kNanosecond    ? 1.0
                         : unit_.at(name) == benchmark::kMicrosecond ? 1e3
                         : unit_.at(name) == benchmark::kMillisecond ? 1e6
                                                                     : 1e9;
    return ns_per_item_.at(name) * scale;
  }

 private:
  std::string baseline_;
  std::map<std::string, double> ns_per_item_;
  std::map<std::string, benchmark::TimeUnit> unit_;
  std::map<std::string, bool> medians_;
};

// BENCHMARK_MAIN() with the ratio table appended (console output only: with
// --benchmark_format=json or csv the output stays machine-readable, without the table).
inline int runWithRatios(int argc, char** argv, const std::string& baseline) {
  bool console = true;
  for (int i = 1; i < argc; ++i)
    if (std::string(argv[i]).rfind("--benchmark_format=", 0) == 0 &&
        std::string(argv[i]) != "--benchmark_format=console")
      console = false;
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  RatioReporter reporter(baseline);
  if (console)
    benchmark::RunSpecifiedBenchmarks(&reporter);
  else
    benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

}  // namespace bench
}  // namespace kane_sim

#endif  // KANE_SIM_BENCH_RATIO_REPORTER_H
