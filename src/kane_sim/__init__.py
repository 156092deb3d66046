"""kane_sim in Python: the textbook example's mechanism ("Kane equations - Example 1") on the
same C++ core as the ROS node and `simulate` (kane_sim._core).

    import kane_sim
    sim = kane_sim.Simulator()                  # config/mechanism.yaml, or a file or a dict
    r = sim.run(2.0, torque=0.5)                # NumPy arrays: r.t, r.q, r.u, r.u_dot, ...
    kane_sim.animate(r)                         # matplotlib animation (notebooks: HTML video)

The generated ROS messages live beside it (kane_sim.msg, kane_sim.srv). Everything here is
imported on first use, so `import kane_sim.msg` in a ROS node loads neither NumPy nor the core.
"""

_CORE = ("Config", "ConfigError", "Result", "Simulator", "StepRefused", "TorqueProfile",
         "analyze", "equilibria", "load_config", "sweep")
_PLOTS = ("animate", "plot_result")
_BATCH = ("BatchSimulator", "VectorEnv")
_ESTIMATE = ("Estimator",)


def __getattr__(name):
    if name in _CORE:
        from kane_sim import core
        return getattr(core, name)
    if name == "BatchSimulator":
        from kane_sim import batch
        return batch.BatchSimulator
    if name == "VectorEnv":
        from kane_sim import vector_env
        return vector_env.VectorEnv
    if name == "Estimator":
        from kane_sim import estimator
        return estimator.Estimator
    if name == "animate":
        from kane_sim.animation import animate
        return animate
    if name == "columns":  # the output table's groups (reads the core)
        import importlib
        return importlib.import_module("kane_sim.columns")
    if name == "plot_result":
        from kane_sim.plotting import plot_result
        return plot_result
    raise AttributeError("module 'kane_sim' has no attribute '%s'" % name)


def __dir__():
    return sorted(list(globals()) + list(_CORE) + list(_PLOTS) + list(_BATCH) + list(_ESTIMATE))
