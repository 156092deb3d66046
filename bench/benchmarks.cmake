# Benchmarks (Google Benchmark, Debian's libbenchmark-dev): built with `all` when found; tools of
# the checkout, not installed.
find_package(benchmark QUIET)
if(benchmark_FOUND)
  #catkin_lint: ignore uninstalled_target
  add_executable(bench_core bench/bench_core.cpp)
  target_link_libraries(bench_core kane_sim_sim benchmark::benchmark kane_sim_warnings)
  target_compile_definitions(bench_core PRIVATE KANE_SIM_CONFIG_DIR="${PROJECT_SOURCE_DIR}/config")
  set_target_properties(bench_core PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${CATKIN_DEVEL_PREFIX}/lib/${PROJECT_NAME})
else()
  message(STATUS "kane_sim: Google Benchmark not found, bench_core is not built")
endif()

# Load generator for the flood test (bench/flood.py).
#catkin_lint: ignore uninstalled_target
add_executable(torque_flood bench/torque_flood.cpp)
target_link_libraries(torque_flood ${catkin_LIBRARIES} kane_sim_warnings)
