# ROS-free unit tests (gtest, no master). Included from CMakeLists.txt.
function(kane_sim_unit_test name)
  catkin_add_gtest(${name} ${ARGN})
  if(TARGET ${name})
    target_link_libraries(${name} kane_sim_core gtest_main)
    target_compile_options(${name} PRIVATE ${KANE_SIM_WARNINGS})
    target_compile_definitions(${name} PRIVATE
      KANE_SIM_CONFIG_DIR="${PROJECT_SOURCE_DIR}/config")
  endif()
endfunction()

kane_sim_unit_test(test_seed_equations test/test_seed_equations.cpp)
kane_sim_unit_test(test_lagrange_crosscheck test/test_lagrange_crosscheck.cpp)
kane_sim_unit_test(test_energy test/test_energy.cpp)
kane_sim_unit_test(test_simulator test/test_simulator.cpp)
kane_sim_unit_test(test_load_config test/test_load_config.cpp)
kane_sim_unit_test(test_simulate_cli test/test_simulate_cli.cpp)
if(TARGET test_simulate_cli)
  add_dependencies(test_simulate_cli simulate)
  target_compile_definitions(test_simulate_cli PRIVATE
    KANE_SIM_SIMULATE_EXE="$<TARGET_FILE:simulate>")
endif()
