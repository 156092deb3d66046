# The ROS-free layers' sources, listed once: the catkin build (CMakeLists.txt) makes one library
# of each; the WebAssembly build (web/CMakeLists.txt) compiles the same files with emscripten.
# Paths are relative to the package root.
set(KANE_SIM_MODEL_SOURCES src/model/constraint_forces.cpp src/model/mechanism_model.cpp
  src/model/power_flow.cpp)
set(KANE_SIM_ANALYSIS_SOURCES src/analysis/analysis_json.cpp src/analysis/equilibria.cpp
  src/analysis/linear_analysis.cpp
  src/analysis/stability.cpp)
set(KANE_SIM_CONFIG_SOURCES src/config/load_config.cpp src/config/parameter_schema.cpp
    src/config/mechanism_parameter_rows.cpp)
set(KANE_SIM_DESCRIPTION_SOURCES src/description/joint_values.cpp
  src/description/robot_description.cpp src/description/urdf.cpp)
set(KANE_SIM_CONTROL_SOURCES src/control/crank_servo.cpp)
set(KANE_SIM_SENSORS_SOURCES src/sensors/joint_sensors.cpp)
# sim: what one mechanism's run needs (the node, simulate, the browser) ...
set(KANE_SIM_SIM_SOURCES
  src/sim/checkpoint.cpp
  src/sim/closed_loop.cpp
  src/sim/config_check.cpp
  src/sim/csv_format.cpp
  src/sim/sim_driver.cpp
  src/sim/held_steps.cpp
  src/sim/contact.cpp
  src/sim/simulator_parameters.cpp
  src/sim/simulator_snapshot.cpp
  src/sim/output_grid.cpp
  src/sim/reconfiguration.cpp
  src/sim/simulator.cpp
  src/sim/state_rates.cpp
  src/sim/torque_command.cpp
  src/sim/torque_profile.cpp)
# ... and many at once (sweeps, batches: SIMD lanes and threads), native builds only.
set(KANE_SIM_SIM_MANY_SOURCES
  src/sim/sweep_csv.cpp
  src/sim/sweep_plan.cpp
  src/sim/lane_sweep.cpp
  src/sim/batch_simulator.cpp
  src/sim/sweep_runner.cpp
  src/sim/numbers_into_configs.cpp
  src/sim/worker_pool.cpp)
# web: the browser's entry points (one run as simulate's CSV, a live session, the drawing's
# outlines, the parameter panel's schema), plain C++ unit-tested natively; its JavaScript
# bindings (src/web/bindings.cpp) are compiled by emscripten only.
set(KANE_SIM_WEB_SOURCES src/web/run_case.cpp src/web/live_session.cpp src/web/outlines.cpp
  src/web/schema_json.cpp)
