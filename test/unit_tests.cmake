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
kane_sim_unit_test(test_torque_command test/test_torque_command.cpp)
kane_sim_unit_test(test_loop_timing test/test_loop_timing.cpp)
kane_sim_unit_test(test_pd_law test/test_pd_law.cpp)
kane_sim_unit_test(test_ros_messages test/test_ros_messages.cpp)
if(TARGET test_ros_messages)
  target_link_libraries(test_ros_messages kane_sim_ros)
endif()
kane_sim_unit_test(test_torque_profile test/test_torque_profile.cpp)
kane_sim_unit_test(test_simulate_bag test/test_simulate_bag.cpp)
if(TARGET test_simulate_bag)
  target_link_libraries(test_simulate_bag kane_sim_ros)
  add_dependencies(test_simulate_bag simulate)
  target_compile_definitions(test_simulate_bag PRIVATE KANE_SIM_SIMULATE_EXE="$<TARGET_FILE:simulate>")
endif()

# Script tests: plots, and rviz under Xvfb replaying a bag (screenshot kept in
# _build/test_artifacts/).
add_test(NAME sympy_crosscheck
  COMMAND /usr/bin/python3 ${PROJECT_SOURCE_DIR}/test/sympy_crosscheck_test.py ${CMAKE_BINARY_DIR})
add_test(NAME plot_bag COMMAND ${PROJECT_SOURCE_DIR}/test/plot_bag_test.sh ${CMAKE_BINARY_DIR})
add_test(NAME rviz_smoke COMMAND ${PROJECT_SOURCE_DIR}/test/rviz_smoke_test.sh ${CMAKE_BINARY_DIR})
set_tests_properties(rviz_smoke PROPERTIES TIMEOUT 120)
