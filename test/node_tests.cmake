# Node tests under rostest: one executable, one .test + .yaml per case (as ros_controllers
# does); each .test runs node_tests with a --gtest_filter. Included from CMakeLists.txt.
find_package(rostest REQUIRED)

catkin_add_executable_with_gtest(node_tests
  test/node/node_test_main.cpp
  test/node/test_topics.cpp
  test/node/test_commands.cpp
  test/node/test_services.cpp
  test/node/test_clock_mode.cpp
  test/node/test_bad_param.cpp
  test/node/test_namespaces.cpp
  test/node/test_controller.cpp
  test/node/test_robustness.cpp
  test/node/test_hostile.cpp
  test/node/test_robot.cpp
  test/node/test_reconfigure.cpp
  test/node/test_by_hand.cpp
  test/node/test_options.cpp
  test/node/test_fuzz.cpp
  test/node/test_resets.cpp
  test/node/test_lockstep.cpp
  test/node/test_sensors.cpp
  test/node/test_servo.cpp
  test/node/test_replay.cpp
  test/node/test_stamps.cpp
  test/node/test_one_truth.cpp
  test/node/test_tracking.cpp
  test/node/test_observer.cpp
  EXCLUDE_FROM_ALL)
if(TARGET node_tests)
  target_include_directories(node_tests PRIVATE ${urdfdom_INCLUDE_DIRS})
  target_link_libraries(node_tests kane_sim_ros kane_sim_design kane_sim_warnings
    ${urdfdom_LIBRARIES})
  target_include_directories(node_tests PRIVATE ${PROJECT_SOURCE_DIR}/test/common
    ${PROJECT_SOURCE_DIR}/examples/pd_controller)
  add_dependencies(tests node_tests)
  # The cases wait on topics and services; their code needs no optimisation, and at -O1 the
  # 24 files compile in about half the time of -O3 (roscpp's and gtest's templates).
  target_compile_options(node_tests PRIVATE -O1)
  target_compile_definitions(node_tests PRIVATE
    KANE_SIM_CONFIG_DIR="${PROJECT_SOURCE_DIR}/config"
    KANE_SIM_SIMULATE_EXE="$<TARGET_FILE:simulate>"
    KANE_SIM_TELEOP_EXE="$<TARGET_FILE:teleop_key>"
    KANE_SIM_NODE_EXE="$<TARGET_FILE:kane_sim_node>")
  foreach(case topics torque commands services clock_mode bad_param namespaces controller
      controller_law robustness
      stalled leftover_sim_time slow_ticks robot_description robot_description_textbook rsp_tf
      reconfigure crank_marker teleop options fuzz resets resets_rsp lockstep lockstep_hog
      lockstep_fallback lockstep_python lockstep_start stamps resets_paused_clock
      resets_paused_clock_rsp one_truth sensors servo
      replay tracking observer observer_tracking controller_table)
    add_rostest(test/node/${case}.test DEPENDENCIES node_tests kane_sim_node pd_controller simulate
      crank_marker teleop_key tracking_controller observer)
  endforeach()
endif()
if(TARGET node_tests)
  # The longest node cases early (see the COST note in unit_tests.cmake).
  set_tests_properties(_ctest_kane_sim_rostest_test_node_options.test PROPERTIES COST 16)
  set_tests_properties(_ctest_kane_sim_rostest_test_node_clock_mode.test PROPERTIES COST 15)
endif()
