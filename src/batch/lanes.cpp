// Choosing the instruction set at run time and cutting the lanes into blocks of its width.
#include <algorithm>
#include <cstdlib>
#include <cstring>
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

// KANE_SIM_SIMD_MAX=<set> makes this process behave as a CPU whose widest set is <set> (as
// MKL_ENABLE_INSTRUCTIONS does for MKL): "auto" picks it, wider ones are refused as absent. The
// test suite runs under each value to prove no test depends on the machine's width. Read once;
// a value that names no set stops the program, naming it.
LaneArch widestAllowed() {
  static const LaneArch widest = [] {
    const char* value = std::getenv("KANE_SIM_SIMD_MAX");
    if (value == nullptr || *value == '\0') return LaneArch::kAvx512;
    for (const ArchEntry& e : kArchs)
      if (std::strcmp(value, e.name) == 0) return e.arch;
    throw std::invalid_argument(std::string("environment variable KANE_SIM_SIMD_MAX '") + value +
                                "' is not one of scalar, sse2, avx2, avx512");
  }();
  return widest;
}

// Why `arch` cannot run here: the CPU lacks it, or the cap above excludes it.
std::string absent(LaneArch arch) {
  if (static_cast<int>(arch) > static_cast<int>(widestAllowed()))
    return std::string("KANE_SIM_SIMD_MAX=") + entry(widestAllowed()).name + " excludes " +
           entry(arch).name;
  return std::string("this CPU has no ") + entry(arch).name;
}

}  // namespace

const char* laneArchName(LaneArch arch) { return entry(arch).name; }
unsigned laneWidth(LaneArch arch) { return entry(arch).width; }

bool laneArchAvailable(LaneArch arch) {
  if (static_cast<int>(arch) > static_cast<int>(widestAllowed())) return false;
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
  if (!laneArchAvailable(arch)) throw std::invalid_argument(absent(arch));
  LaneMathValues out;
  out.sines.resize(values.size());
  out.cosines.resize(values.size());
  out.tanhs.resize(values.size());
  entry(arch).math(values.data(), values.size(), out.sines.data(), out.cosines.data(),
                   out.tanhs.data());
  return out;
}

void checkLaneEnvironment() { widestAllowed(); }

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
      throw std::invalid_argument("simd '" + name + "': " + absent(e.arch) +
                                  " (the widest it runs is " + laneArchName(bestLaneArch()) + ")");
    return e.arch;
  }
  throw std::invalid_argument("simd '" + name +
                              "' is not one of auto, avx512, avx2, sse2, scalar, off");
}

namespace {
// LaneRun::packed: per block of `width` lanes, each constant's column, then the torque limits'
// and the reaches' (|x_B| <= 4L).
constexpr size_t kPackedColumns = sizeof(generated::Constants) / sizeof(double) + 2;
size_t packedSize(size_t lanes, size_t width) {
  return (lanes + width - 1) / width * width * kPackedColumns;
}
}  // namespace

void packLanes(LaneRun& run, LaneArch arch) {
  const size_t n = run.constants.size(), width = entry(arch).width;
  if (run.torque_limit.size() != n)
    throw std::invalid_argument("packLanes: constants and torque_limit differ in length");
  run.packed.assign(packedSize(n, width), 0.0);
  run.packed_width = static_cast<unsigned>(width);
  constexpr size_t kConstants = kPackedColumns - 2;
  for (size_t first = 0; first < n; first += width) {
    double* block = run.packed.data() + first * kPackedColumns;
    for (size_t j = 0; j < width; ++j) {
      const size_t i = std::min(first + j, n - 1);  // as the block's padding lanes
      const double* constants = reinterpret_cast<const double*>(&run.constants[i]);
      for (size_t f = 0; f < kConstants; ++f) block[f * width + j] = constants[f];
      block[kConstants * width + j] = run.torque_limit[i];
      block[(kConstants + 1) * width + j] = slider3Position(run.constants[i].rod_half_length, 1.0);
    }
  }
}

std::vector<LaneOutcome> runLanes(const LaneRun& run, LaneArch arch) {
  std::vector<LaneOutcome> out(run.start.size());
  runLanes(run, arch, out.data());
  return out;
}

void runLanes(const LaneRun& run, LaneArch arch, LaneOutcome* out) {
  const size_t n = run.constants.size();
  if (run.torque_limit.size() != n || run.start.size() != n)
    throw std::invalid_argument("runLanes: constants, torque_limit and start differ in length");
  const bool per_lane = !run.lane_command.empty();
  if (per_lane && run.lane_command.size() != n)
    throw std::invalid_argument("runLanes: lane_command must hold one torque per lane");
  const ArchEntry& e = entry(arch);
  const bool packed = run.packed_width == e.width && run.packed.size() == packedSize(n, e.width);
  for (size_t first = 0; first < n; first += e.width) {
    LaneBlock block{run.constants.data(),
                    packed ? run.packed.data() + first * kPackedColumns : nullptr,
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
                    out + first};
    e.run(block);
  }
}

}  // namespace kane_sim
