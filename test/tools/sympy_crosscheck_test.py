#!/usr/bin/python3
"""Independent derivation #2 (after the Lagrange test): SymPy's KanesMethod, built from the
geometry alone, gives the same u' as kane_sim along simulated trajectories, for both
inertias, a driven crank, all five dampers, the four joints' Coulomb friction and the crank's
torsional spring (as loads), on both of kane_sim's paths
(simulation.equations generated and generic). Measured agreement ~1e-13; the bound 1e-9 (relative to
1 + |u'|) is far below any modelling error, which would be O(1); with the torsional spring alone
(the load added last, the one a slip would hide in) the bound is 1e-12.
Usage: sympy_crosscheck_test.py BUILD_DIR
"""
import os
import subprocess
import sys
import tempfile

import yaml

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from sympy_model import sympy_model  # noqa: E402


def main(build_dir):
    simulate = os.path.join(build_dir, "devel/lib/kane_sim/simulate")
    failures = 0
    dampers = {"crank_joint": 0.3, "coupler_joint": 0.2, "slider3_joint": 1.5, "slider4_joint": 2.0,
               "spring": 0.8}
    friction = {"crank_joint": 0.4, "coupler_joint": 0.1, "slider3_joint": 2.0,
                "slider4_joint": 1.5, "velocity_scale": 0.2}
    crank_spring = {"crank_spring_stiffness": 15.0, "crank_spring_rest_angle": 0.8}
    cases = [(config_name, torque, damping, rubbing, spring, equations)
             for config_name, torque, damping, rubbing, spring in (
                 ("mechanism.yaml", 0.0, None, None, None),
                 ("mechanism.yaml", 12.0, None, None, None),
                 ("textbook.yaml", 4.0, None, None, None),
                 ("mechanism.yaml", 6.0, dampers, None, None),
                 ("mechanism.yaml", 6.0, None, friction, None),
                 ("mechanism.yaml", 6.0, dampers, friction, None),
                 ("mechanism.yaml", 2.0, None, None, crank_spring),
                 ("mechanism.yaml", 6.0, dampers, friction, crank_spring))
             for equations in ("generated", "generic")]
    for config_name, torque, damping, rubbing, spring, equations in cases:
        with open(os.path.join(HERE, "..", "..", "config", config_name)) as f:
            config = yaml.safe_load(f)
        config["mechanism"].update(spring or {})
        # The published u' comes from the equations the integrators step: both paths are checked.
        config["simulation"]["equations"] = equations
        if damping:
            config["damping"] = damping
        if rubbing:
            config["friction"] = rubbing
        with tempfile.NamedTemporaryFile("w", suffix=".yaml", delete=False) as f:
            yaml.safe_dump(config, f)
        path = f.name
        label = "%s%s%s%s, %s equations" % (
            config_name, " with dampers" if damping else "", " with friction" if rubbing else "",
            " with the torsional spring" if spring else "", equations)
        s0 = config["initial_state"]
        rhs = sympy_model(config["mechanism"], [s0["q1"], s0["q2"]], torque, config.get("damping"),
                          config.get("friction") if rubbing else None)
        out = subprocess.run([simulate, "--config", path, "--duration", "5", "--output-rate", "20",
                              "--torque", str(torque)], capture_output=True, text=True, check=True).stdout
        os.unlink(path)
        lines = out.strip().splitlines()
        header = lines[0].split(",")
        col = {name: i for i, name in enumerate(header)}
        worst = 0.0
        for line in lines[1:]:
            v = [float(x) for x in line.split(",")]
            expected = rhs(0.0, [v[col["q1"]], v[col["q2"]], v[col["u1"]], v[col["u2"]]])[2:]
            for got, want in zip((v[col["u1dot"]], v[col["u2dot"]]), expected):
                worst = max(worst, abs(got - want) / (1 + abs(want)))
        ok = worst < (1e-12 if spring and not (damping or rubbing) else 1e-9)
        failures += not ok
        print("%s %s, torque %g N m: max relative |u'(kane_sim) - u'(SymPy)| = %.2e over %d states"
              % ("ok  " if ok else "FAIL", label, torque, worst, len(lines) - 1))
    print("%d passed, %d failed" % (len(cases) - failures, failures))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
