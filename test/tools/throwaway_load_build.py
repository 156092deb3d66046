#!/usr/bin/python3
"""A load is one declaration, through every consumer: a copy of the package gets a throw-away
viscous damper on slider 4 (coefficient c_T, key damping.throwaway) written the way
doc/design/architecture.md's "Adding a load" says — one row of the parameter table
(codegen/parameters.yaml) and one LOADS row in the code generator, then the generator run — and
nothing else. The copy is built (the ROS-free tools, the Python
module and two test binaries) and every consumer is asked for the new load:

- the schema and its documented table (config_info parameters: role, symbol, reconfigure name);
- the output table (config_info outputs: its power column power_throwaway_damper);
- the generated and the generic equations agree with it on (test_generated_equations'
  every-parameter test and test_parameter_schema walk the schema, so they test the new row);
- Python: Config.names(role="dissipative"), Config.reconfigurable, identify.parameters(), a run's
  Result.powers["throwaway_damper"] (<= 0, not all 0), its ledger (closes with the new load's
  work counted as dissipated), the SIMD lanes of a sweep (equal to the single runs, bit for bit)
  and BatchSimulator (equal to Simulator);
- analyze (the linearization's damping changes with c_T).

The build takes minutes on two cores, so this test carries the ctest label "slow": the README's
test command leaves it out; run it with `ctest -L slow` (doc/guide/testing.md).
Usage: throwaway_load_build.py [--keep]   (--keep leaves the copy and its build in /tmp)
"""
import os
import shutil
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
PACKAGE = os.path.normpath(os.path.join(HERE, "..", ".."))

# The declaration, as the recipe writes it: (file, anchor, text inserted after the anchor).
EDITS = [
    ("codegen/parameters.yaml",
     '    doc: "beside the spring: −c_S (v_C − v_B) on slider 4, the opposite on slider 3"\n',
     '  - key: damping.throwaway\n'
     '    symbol: c_T\n'
     '    unit: N s/m\n'
     '    rule: non-negative\n'
     '    default: 0\n'
     '    role: dissipative\n'
     '    reconfigure: {name: throwaway_damping, min: 0, max: 1e4}\n'
     '    doc: a throw-away damper on slider 4\n'),
    ("codegen/generate_equations.py",
     '    ("spring_damper",   "resistance",   "spring",  "viscous", "c_S", None),\n',
     '    ("throwaway_damper", "resistance", "slider4", "viscous", "c_T", None),\n'),
]

PYTHON_CHECKS = r"""
import numpy as np
import kane_sim
from kane_sim import _core, identify
key = "damping.throwaway"
assert key in kane_sim.Config.names(role="dissipative"), "role"
assert _core.Config.reconfigurable(key), "reconfigure"
assert key in [p["name"] for p in identify.parameters() if p["by_default"]], "identify"
cfg = kane_sim.Config().with_values({key: 2.0, "simulation.integrator": "dopri5"})
r = kane_sim.Simulator(cfg).run(5.0, torque=kane_sim.TorqueProfile.sine(3, 0.7))
p = r.powers["throwaway_damper"]
assert np.all(p <= 0) and np.min(p) < -1e-3, "power"
balance = r.ledger["energy_balance"]
assert np.ptp(balance) < 1e-8, ("ledger", np.ptp(balance))
assert r["dissipated_energy"][-1] > 1e-3, "dissipated"
# SIMD lanes (rk4 cases) equal the single runs; BatchSimulator equals Simulator.
rk4 = kane_sim.Config().with_values({key: 2.0})
lanes = _core.sweep(rk4._core, [key], [[1.0], [2.0], [3.0]], 2.0,
                    _core.TorqueProfile.constant(1.5), 1, "scalar", False)
alone = _core.sweep(rk4._core, [key], [[1.0], [2.0], [3.0]], 2.0,
                    _core.TorqueProfile.constant(1.5), 1, "off", False)
for c in ("q1", "q2", "u1", "u2", "dissipated_energy"):
    assert np.array_equal(lanes[c], alone[c]), ("lanes", c)
batch = kane_sim.BatchSimulator(3, rk4)
batch.step(np.full(3, 1.5), steps=500)
sim = kane_sim.Simulator(rk4)
sim.set_torque(1.5)
state = sim.step(500)
assert np.array_equal(batch.states[0], state), ("batch", batch.states[0], state)
a0 = kane_sim.analyze(kane_sim.Config())
a1 = kane_sim.analyze(kane_sim.Config().with_values({key: 5.0}))
assert a0 != a1, "analyze"
print("python: every consumer sees the throw-away load")
"""


def run(command, **kw):
    print("+ " + " ".join(command), flush=True)
    return subprocess.run(command, check=True, **kw)


def main():
    keep = "--keep" in sys.argv[1:]
    work = tempfile.mkdtemp(prefix="kane_sim_throwaway_")
    try:
        copy, build = os.path.join(work, "kane_sim"), os.path.join(work, "build")
        shutil.copytree(PACKAGE, copy, ignore=shutil.ignore_patterns(".git", "build*"))
        for path, anchor, text in EDITS:
            full = os.path.join(copy, path)
            with open(full) as f:
                source = f.read()
            if source.count(anchor) != 1:
                sys.exit("%s: the recipe's anchor is gone (update this test): %r" % (path, anchor))
            with open(full, "w") as f:
                f.write(source.replace(anchor, anchor + text))
        run(["/usr/bin/python3", os.path.join(copy, "codegen", "generate_equations.py")])
        run(["cmake", "-S", copy, "-B", build, "-DCMAKE_BUILD_TYPE=Release",
             "-DPYTHON_EXECUTABLE=/usr/bin/python3", "-DPython3_EXECUTABLE=/usr/bin/python3"],
            stdout=subprocess.DEVNULL)
        run(["cmake", "--build", build, "-j2", "--target", "config_info", "kane_sim_python",
             "test_generated_equations", "test_parameter_schema"], stdout=subprocess.DEVNULL)
        bash = ("set +u; source %s/devel/setup.bash; set -u; " % build)
        tables = subprocess.run(["bash", "-c", bash + "rosrun kane_sim config_info parameters; "
                                 "rosrun kane_sim config_info outputs"], check=True,
                                capture_output=True, text=True).stdout
        row = [line for line in tables.splitlines() if line.startswith("| damping.throwaway |")]
        assert row and "dissipative" in row[0] and "c_T" in row[0] and \
            "throwaway_damping" in row[0], ("parameters table", row)
        assert "| `power_throwaway_damper` | power |" in tables, "outputs table"
        print("config_info: the row and the power column are there", flush=True)
        for test in ("test_generated_equations", "test_parameter_schema"):
            binary = [os.path.join(root, test) for root, _, files in os.walk(build)
                      if test in files][0]
            # TheDocumentedTableIsTheSchemas compares with the copy's page, which this test
            # does not regenerate: the table itself was checked above.
            run(["bash", "-c", bash + binary +
                 " --gtest_filter=-ParameterSchema.TheDocumentedTableIsTheSchemas"],
                stdout=subprocess.DEVNULL)
        run(["bash", "-c", bash + "/usr/bin/python3 -"], input=PYTHON_CHECKS, text=True)
        print("throwaway_load_build: ok", flush=True)
    finally:
        if keep:
            print("kept %s" % work)
        else:
            shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
