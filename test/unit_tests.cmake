# Unit tests (gtest, no master). Included from CMakeLists.txt.
#   kane_sim_unit_test(NAME SOURCES... [ROS] [RUNS_SIMULATE])
# ROS: also links the message-filling library; RUNS_SIMULATE: the test runs the `simulate`
# executable (built first, its path in KANE_SIM_SIMULATE_EXE).
function(kane_sim_unit_test name)
  cmake_parse_arguments(ARG "ROS;RUNS_SIMULATE" "" "" ${ARGN})
  catkin_add_gtest(${name} ${ARG_UNPARSED_ARGUMENTS})
  if(NOT TARGET ${name})
    return()
  endif()
  target_link_libraries(${name} kane_sim_core gtest_main)
  target_compile_options(${name} PRIVATE ${KANE_SIM_WARNINGS})
  target_compile_definitions(${name} PRIVATE KANE_SIM_CONFIG_DIR="${PROJECT_SOURCE_DIR}/config")
  if(ARG_ROS)
    target_link_libraries(${name} kane_sim_ros)
  endif()
  if(ARG_RUNS_SIMULATE)
    add_dependencies(${name} simulate)
    target_compile_definitions(${name} PRIVATE KANE_SIM_SIMULATE_EXE="$<TARGET_FILE:simulate>")
  endif()
endfunction()

kane_sim_unit_test(test_seed_equations test/test_seed_equations.cpp)
kane_sim_unit_test(test_lagrange_crosscheck test/test_lagrange_crosscheck.cpp)
kane_sim_unit_test(test_energy test/test_energy.cpp)
kane_sim_unit_test(test_simulator test/test_simulator.cpp)
kane_sim_unit_test(test_load_config test/test_load_config.cpp)
kane_sim_unit_test(test_simulate_cli test/test_simulate_cli.cpp RUNS_SIMULATE)
kane_sim_unit_test(test_torque_command test/test_torque_command.cpp)
kane_sim_unit_test(test_loop_timing test/test_loop_timing.cpp)
kane_sim_unit_test(test_pd_law test/test_pd_law.cpp)
kane_sim_unit_test(test_ros_messages test/test_ros_messages.cpp ROS)
kane_sim_unit_test(test_torque_profile test/test_torque_profile.cpp)
kane_sim_unit_test(test_simulate_bag test/test_simulate_bag.cpp ROS RUNS_SIMULATE)

# Script tests: plots, and rviz under Xvfb replaying a bag (screenshot kept in
# _build/test_artifacts/).
add_test(NAME sympy_crosscheck
  COMMAND /usr/bin/python3 ${PROJECT_SOURCE_DIR}/test/sympy_crosscheck_test.py ${CMAKE_BINARY_DIR})
add_test(NAME plot_bag COMMAND ${PROJECT_SOURCE_DIR}/test/plot_bag_test.sh ${CMAKE_BINARY_DIR})
add_test(NAME rviz_smoke COMMAND ${PROJECT_SOURCE_DIR}/test/rviz_smoke_test.sh ${CMAKE_BINARY_DIR})
set_tests_properties(rviz_smoke PROPERTIES TIMEOUT 120)
add_test(NAME faults COMMAND ${PROJECT_SOURCE_DIR}/test/faults_test.sh ${CMAKE_BINARY_DIR})
set_tests_properties(faults PROPERTIES TIMEOUT 180)
