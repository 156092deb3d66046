// Loads simulate's bag half (bag_module.h) when a run first asks for a bag.
#include <dlfcn.h>

#include <filesystem>
#include <stdexcept>
#include <string>

#include "simulate/bag_module.h"

namespace simulate {
namespace {

// simulate is lib/kane_sim/simulate (devel or install); its libraries are in lib/.
std::string besideTheLibraries() {
  std::error_code error;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", error);
  if (error) return "";
  return (self.parent_path().parent_path() / kBagModuleLibrary).string();
}

const BagModule& load() {
  void* handle = nullptr;
  const std::string beside = besideTheLibraries();
  if (!beside.empty() && std::filesystem::exists(beside))
    handle = dlopen(beside.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) handle = dlopen(kBagModuleLibrary, RTLD_NOW | RTLD_LOCAL);
  if (!handle)
    throw std::runtime_error(std::string("cannot load ") + kBagModuleLibrary +
                             ", simulate's bag support (--bag, --replay): " + dlerror() +
                             " (rebuild the package, or source its setup.bash)");
  using Entry = const BagModule* (*)();
  const auto entry = reinterpret_cast<Entry>(dlsym(handle, kBagModuleSymbol));
  if (!entry)
    throw std::runtime_error(std::string(kBagModuleLibrary) + " lacks " + kBagModuleSymbol +
                             ": it is not this simulate's (rebuild the package)");
  return *entry();
}

}  // namespace

const BagModule& bagModule() {
  static const BagModule& module = load();  // a failed load throws, and is tried again next time
  return module;
}

}  // namespace simulate
