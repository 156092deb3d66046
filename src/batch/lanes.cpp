// Choosing the instruction set at run time and cutting the lanes into blocks of its width.
#include <stdexcept>

#include <xsimd/config/xsimd_cpuid.hpp>

#include "lane_block.h"

namespace kane_sim {

namespace {

struct ArchEntry {
  LaneArch arch;
  const char* name;
  unsigned width;
  void (*run)(const LaneBlock&);
  LaneMathRun math;
};

constexpr ArchEntry kArchs[] = {
    {LaneArch::kScalar, "scalar", 1, runLaneBlockScalar, laneMathScalar},
    {LaneArch::kSse2, "sse2", 2, runLaneBlockSse2, laneMathSse2},
    {LaneArch::kAvx2, "avx2", 4, runLaneBlockAvx2, laneMathAvx2},
    {LaneArch::kAvx512, "avx512", 8, runLaneBlockAvx512, laneMathAvx512},
};

const ArchEntry& entry(LaneArch arch) { return kArchs[static_cast<int>(arch)]; }

}  // namespace

const char* laneArchName(LaneArch arch) { return entry(arch).name; }
unsigned laneWidth(LaneArch arch) { return entry(arch).width; }

bool laneArchAvailable(LaneArch arch) {
  const auto cpu = xsimd::available_architectures();  // cpuid and the OS's saved registers
  switch (arch) {
    case LaneArch::kScalar:
      return true;
    case LaneArch::kSse2:
      return cpu.sse2;
    case LaneArch::kAvx2:
      return cpu.avx2;
    case LaneArch::kAvx512:
      return cpu.avx512f;
  }
  return false;
}

LaneMathValues laneMathFunctions(LaneArch arch, const std::vector<double>& values) {
  if (!laneArchAvailable(arch))
    throw std::invalid_argument(std::string("this CPU has no ") + laneArchName(arch));
  LaneMathValues out;
  out.sines.resize(values.size());
  out.cosines.resize(values.size());
  out.tanhs.resize(values.size());
  entry(arch).math(values.data(), values.size(), out.sines.data(), out.cosines.data(),
                   out.tanhs.data());
  return out;
}

LaneArch bestLaneArch() {
  for (LaneArch arch : {LaneArch::kAvx512, LaneArch::kAvx2, LaneArch::kSse2})
    if (laneArchAvailable(arch)) return arch;
  return LaneArch::kScalar;
}

LaneArch parseLaneArch(const std::string& name) {
  if (name == "auto") return bestLaneArch();
  for (const ArchEntry& e : kArchs) {
    if (name != e.name) continue;
    if (!laneArchAvailable(e.arch))
      throw std::invalid_argument("simd '" + name + "': this CPU has no " + name +
                                  " (the widest it runs is " + laneArchName(bestLaneArch()) + ")");
    return e.arch;
  }
  throw std::invalid_argument("simd '" + name +
                              "' is not one of auto, avx512, avx2, sse2, scalar, off");
}

std::vector<LaneOutcome> runLanes(const LaneRun& run, LaneArch arch) {
  const size_t n = run.constants.size();
  if (run.torque_limit.size() != n || run.start.size() != n)
    throw std::invalid_argument("runLanes: constants, torque_limit and start differ in length");
  const bool per_lane = !run.lane_command.empty();
  if (per_lane && run.lane_command.size() != n)
    throw std::invalid_argument("runLanes: lane_command must hold one torque per lane");
  std::vector<LaneOutcome> out(n);
  const ArchEntry& e = entry(arch);
  for (size_t first = 0; first < n; first += e.width) {
    LaneBlock block{run.constants.data(),
                    run.torque_limit.data(),
                    run.start.data(),
                    run.variant,
                    run.step,
                    run.command.data(),
                    per_lane ? run.lane_command.data() : nullptr,
                    per_lane ? run.held_steps : static_cast<long>(run.command.size()),
                    run.stop_at_crossing,
                    run.steps_per_sample,
                    run.stop,
                    run.on_sample,
                    run.sample_context,
                    run.vector_trig,
                    first,
                    std::min<size_t>(e.width, n - first),
                    out.data() + first};
    e.run(block);
  }
  return out;
}

}  // namespace kane_sim
