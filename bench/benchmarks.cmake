# Benchmarks (Google Benchmark, Debian's libbenchmark-dev): built with `all` when found; tools of
# the checkout, not installed. Their binaries go to BUILD/bench_bin, outside the package's
# executables (devel/lib/kane_sim), so `rosrun kane_sim <TAB>` lists the user's tools only.
set(KANE_SIM_BENCH_BIN ${CMAKE_BINARY_DIR}/bench_bin)
find_package(benchmark QUIET)
if(benchmark_FOUND)
  #catkin_lint: ignore uninstalled_target
  add_executable(bench_core bench/bench_core.cpp)
  target_link_libraries(bench_core kane_sim_sim benchmark::benchmark kane_sim_warnings)
  target_compile_definitions(bench_core PRIVATE KANE_SIM_CONFIG_DIR="${PROJECT_SOURCE_DIR}/config")
  set_target_properties(bench_core PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${KANE_SIM_BENCH_BIN})
  #catkin_lint: ignore uninstalled_target
  add_executable(bench_design bench/bench_design.cpp)
  target_link_libraries(bench_design kane_sim_plan benchmark::benchmark kane_sim_warnings)
  target_compile_definitions(bench_design PRIVATE KANE_SIM_CONFIG_DIR="${PROJECT_SOURCE_DIR}/config")
  set_target_properties(bench_design PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${KANE_SIM_BENCH_BIN})
  # The peers side by side (MuJoCo, Debian's libmujoco-dev: bench/run_all.sh installs it).
  # Found by hand: Debian 12's mujocoConfig.cmake names /usr/include/libqhull_r, which only
  # libqhull-dev provides, and the headers here do not need.
  find_library(MUJOCO_LIBRARY mujoco)
  find_path(MUJOCO_INCLUDE_DIR mujoco/mujoco.h)
  if(MUJOCO_LIBRARY AND MUJOCO_INCLUDE_DIR)
    #catkin_lint: ignore uninstalled_target
    add_executable(bench_peers bench/bench_peers.cpp)
    target_include_directories(bench_peers SYSTEM PRIVATE ${MUJOCO_INCLUDE_DIR})
    target_link_libraries(bench_peers kane_sim_sim ${MUJOCO_LIBRARY} benchmark::benchmark
      kane_sim_warnings)
    target_compile_definitions(bench_peers PRIVATE KANE_SIM_CONFIG_DIR="${PROJECT_SOURCE_DIR}/config")
    set_target_properties(bench_peers PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${KANE_SIM_BENCH_BIN})
    # Simbody (Debian's libsimbody-dev), when installed: an accuracy peer with exact loop closure.
    find_package(Simbody QUIET)
    if(Simbody_FOUND)
      target_include_directories(bench_peers SYSTEM PRIVATE ${Simbody_INCLUDE_DIR})
      target_link_libraries(bench_peers ${Simbody_LIBRARIES})
      target_compile_definitions(bench_peers PRIVATE KANE_SIM_HAVE_SIMBODY)
    endif()
  else()
    message(STATUS "kane_sim: MuJoCo not found, bench_peers is not built")
  endif()
else()
  message(STATUS "kane_sim: Google Benchmark not found, bench_core is not built")
endif()

# Load generator for the flood test (bench/flood.py).
#catkin_lint: ignore uninstalled_target
add_executable(torque_flood bench/torque_flood.cpp)
target_link_libraries(torque_flood ${catkin_LIBRARIES} kane_sim_warnings)
set_target_properties(torque_flood PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${KANE_SIM_BENCH_BIN})
