"""The textbook example's mechanism built independently with SymPy's KanesMethod (sympy.physics.mechanics),
from the geometry in doc/theory/mechanism.md only. Used by test/tools/sympy_crosscheck_test.py and
bench/compare_sympy.py.

Independent on purpose: this is a test oracle, so it shares nothing with the code it checks -
not codegen/generate_equations.py's derivation (which generates the C++ fast path), not the
config loader (parameters arrive as plain numbers, the rod inertia default is written again
below), not the generic Kane assembly. A mistake in the shared derivation would otherwise pass
its own test. The Lagrange cross-check (test/core/test_lagrange_crosscheck.cpp) and the Simbody
and MuJoCo peers (bench/) are independent in the same way."""
import math

import numpy as np
import sympy as sp
import sympy.physics.mechanics as me


def sympy_model(params, x0, torque=0.0, damping=None, friction=None):
    """params: the config's mechanism map; x0: (q10, q20, ...), where the spring is unstretched;
    damping: the config's damping map (joint name -> coefficient), absent = none;
    friction: the config's friction map (joint name -> Coulomb force or torque, velocity_scale),
    absent = none.
    Returns f(t, x) with x' = f for x = (q1, q2, u1, u2) and a constant driver moment."""
    q1, q2, u1, u2 = me.dynamicsymbols("q1 q2 u1 u2")
    frame = me.ReferenceFrame("N")  # N.x = i points down, gravity along +x
    rod1 = frame.orientnew("R1", "Axis", [q1, frame.z])
    rod2 = frame.orientnew("R2", "Axis", [-q1, frame.z])
    rod1.set_ang_vel(frame, u1 * frame.z)
    rod2.set_ang_vel(frame, -u1 * frame.z)
    o = me.Point("O")
    o.set_vel(frame, 0)
    p = params
    L = p["rod_half_length"]
    points = {
        "C1": o.locatenew("C1", L * rod1.x),
        "C2": o.locatenew("C2", 2 * L * rod1.x + L * rod2.x),
        "B": o.locatenew("B", 4 * L * sp.cos(q1) * frame.x),
        "C": o.locatenew("C", q2 * frame.x),
    }
    qdot = {q1.diff(): u1, q2.diff(): u2}
    for point in points.values():
        point.set_vel(frame, point.pos_from(o).dt(frame).subs(qdot))
    m, g, k = p["rod_mass"], p["gravity"], p["spring_stiffness"]
    inertia = p.get("rod_inertia", m * (2 * L) ** 2 / 12)
    bodies = [
        me.RigidBody("rod1", points["C1"], rod1, m, (me.inertia(rod1, 0, 0, inertia), points["C1"])),
        me.RigidBody("rod2", points["C2"], rod2, m, (me.inertia(rod2, 0, 0, inertia), points["C2"])),
        me.Particle("slider3", points["B"], p["slider3_mass"]),
        me.Particle("slider4", points["C"], p["slider4_mass"]),
    ]
    elongation = (4 * L * sp.cos(q1) - q2) - (4 * L * math.cos(x0[0]) - x0[1])
    loads = [
        (points["C1"], m * g * frame.x),
        (points["C2"], m * g * frame.x),
        (points["B"], p["slider3_mass"] * g * frame.x - k * elongation * frame.x),
        (points["C"], p["slider4_mass"] * g * frame.x + k * elongation * frame.x),
        (rod1, torque * frame.z),
        # a torsional spring at O, pulling rod 1 back to its rest angle
        (rod1, -p.get("crank_spring_stiffness", 0.0) * (q1 - p.get("crank_spring_rest_angle", 0.0))
         * frame.z),
    ]
    # Viscous dampers as loads: torques on the rods' frames from the joint rates (pin O: w1;
    # pin A: w2 - w1, reaction on rod 1), forces at B and C against their velocities, and the
    # damper beside the spring on the sliders' relative velocity.
    c = {"crank_joint": 0.0, "coupler_joint": 0.0, "slider3_joint": 0.0, "slider4_joint": 0.0,
         "spring": 0.0}
    c.update(damping or {})
    w1, w2 = rod1.ang_vel_in(frame).dot(frame.z), rod2.ang_vel_in(frame).dot(frame.z)
    loads += [
        (rod1, (-c["crank_joint"] * w1 + c["coupler_joint"] * (w2 - w1)) * frame.z),
        (rod2, -c["coupler_joint"] * (w2 - w1) * frame.z),
        (points["B"], -c["slider3_joint"] * points["B"].vel(frame)),
        (points["C"], -c["slider4_joint"] * points["C"].vel(frame)),
        # beside the spring, on the sliders' relative velocity
        (points["C"], -c["spring"] * (points["C"].vel(frame) - points["B"].vel(frame))),
        (points["B"], c["spring"] * (points["C"].vel(frame) - points["B"].vel(frame))),
    ]
    # Coulomb friction, smoothed, against each joint's rate: the crank's pin turns at w1, the
    # coupler's at w2 - w1 (rod 2 relative to rod 1), the sliders move at v_B and v_C.
    f = {"crank_joint": 0.0, "coupler_joint": 0.0, "slider3_joint": 0.0, "slider4_joint": 0.0,
         "velocity_scale": 0.01}
    f.update(friction or {})
    vs = f["velocity_scale"]
    v_b = points["B"].vel(frame).dot(frame.x)
    v_c = points["C"].vel(frame).dot(frame.x)
    pin_a = f["coupler_joint"] * sp.tanh((w2 - w1) / vs)
    loads += [
        (rod1, (-f["crank_joint"] * sp.tanh(w1 / vs) + pin_a) * frame.z),
        (rod2, -pin_a * frame.z),
        (points["B"], -f["slider3_joint"] * sp.tanh(v_b / vs) * frame.x),
        (points["C"], -f["slider4_joint"] * sp.tanh(v_c / vs) * frame.x),
    ]
    kane = me.KanesMethod(frame, q_ind=[q1, q2], u_ind=[u1, u2],
                          kd_eqs=[q1.diff() - u1, q2.diff() - u2])
    kane.kanes_equations(bodies, loads)
    mass = sp.lambdify([q1, q2, u1, u2], kane.mass_matrix_full, "numpy")
    forcing = sp.lambdify([q1, q2, u1, u2], kane.forcing_full, "numpy")

    def rhs(_t, x):
        return np.linalg.solve(mass(*x), forcing(*x)).ravel()

    return rhs
