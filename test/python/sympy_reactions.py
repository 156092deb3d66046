"""The reaction forces of the textbook example's mechanism from SymPy's KanesMethod with
auxiliary speeds (u_auxiliary), built from doc/theory/mechanism.md only: a test oracle for
kane_sim's model/constraint_forces.cpp, independent of it (a different set of auxiliary motions:
each pin released as a relative velocity along the chain O -> A -> B, SymPy forming every term).

Unknowns, each on the second body from the first, in frame N (x down, y horizontal):
O_x, O_y (ground -> rod 1 at O), A_x, A_y (rod 1 -> rod 2), B_x, B_y (rod 2 -> slider 3),
N3, N4 (the rails -> sliders 3, 4 along y)."""
import math

import numpy as np
import sympy as sp
import sympy.physics.mechanics as me

REACTIONS = ["O_x", "O_y", "A_x", "A_y", "B_x", "B_y", "N3", "N4"]


def reaction_model(p, x0, damping):
    """p: the config's mechanism map; x0: the initial state (q10, q20) where the spring is
    unstretched; damping: joint name -> coefficient. Returns f(state, torque) -> dict of the
    eight reactions."""
    q1, q2, u1, u2 = me.dynamicsymbols("q1 q2 u1 u2")
    ua = me.dynamicsymbols("ua1:9")  # the auxiliary speeds
    lam = sp.symbols(" ".join(REACTIONS))
    Ox, Oy, Ax, Ay, Bx, By, N3, N4 = lam
    N = me.ReferenceFrame("N")
    R1 = N.orientnew("R1", "Axis", [q1, N.z])
    R2 = N.orientnew("R2", "Axis", [-q1, N.z])
    R1.set_ang_vel(N, u1 * N.z)
    R2.set_ang_vel(N, (-u1 + ua[6]) * N.z)  # ua7: rod 2 turns about A on its own
    L = p["rod_half_length"]
    m, g, k = p["rod_mass"], p["gravity"], p["spring_stiffness"]
    inertia = p.get("rod_inertia", m * (2 * L) ** 2 / 12)
    O = me.Point("O")
    O.set_vel(N, ua[0] * N.x + ua[1] * N.y)  # ua1, ua2: pin O released
    C1 = O.locatenew("C1", L * R1.x)
    C1.v2pt_theory(O, N, R1)
    A1 = O.locatenew("A1", 2 * L * R1.x)  # A on rod 1
    A1.v2pt_theory(O, N, R1)
    A2 = O.locatenew("A2", 2 * L * R1.x)  # A on rod 2: ua3, ua4 release pin A
    A2.set_vel(N, A1.vel(N) + ua[2] * N.x + ua[3] * N.y)
    C2 = A2.locatenew("C2", L * R2.x)
    C2.v2pt_theory(A2, N, R2)
    B2 = A2.locatenew("B2", 2 * L * R2.x)  # B on rod 2
    B2.v2pt_theory(A2, N, R2)
    B3 = A2.locatenew("B3", 2 * L * R2.x)  # slider 3: ua5, ua6 release pin B
    B3.set_vel(N, B2.vel(N) + ua[4] * N.x + ua[5] * N.y)
    C4 = O.locatenew("C4", q2 * N.x)  # slider 4 on its rail: ua8 lifts it off
    C4.set_vel(N, u2 * N.x + ua[7] * N.y)
    bodies = [
        me.RigidBody("rod1", C1, R1, m, (me.inertia(R1, 0, 0, inertia), C1)),
        me.RigidBody("rod2", C2, R2, m, (me.inertia(R2, 0, 0, inertia), C2)),
        me.Particle("slider3", B3, p["slider3_mass"]),
        me.Particle("slider4", C4, p["slider4_mass"]),
    ]
    torque = sp.Symbol("M_m")
    e = (4 * L * sp.cos(q1) - q2) - (4 * L * math.cos(x0[0]) - x0[1])
    c = {"crank_joint": 0.0, "coupler_joint": 0.0, "slider3_joint": 0.0, "slider4_joint": 0.0,
         "spring": 0.0}
    c.update(damping or {})
    w1, w2 = u1, -u1  # the real joint rates
    v_b = -4 * L * sp.sin(q1) * u1
    loads = [
        (C1, m * g * N.x), (C2, m * g * N.x),
        (B3, (p["slider3_mass"] * g - k * e - c["slider3_joint"] * v_b
              + c["spring"] * (u2 - v_b)) * N.x),
        (C4, (p["slider4_mass"] * g + k * e - c["slider4_joint"] * u2
              - c["spring"] * (u2 - v_b)) * N.x),
        (R1, (torque - c["crank_joint"] * w1 + c["coupler_joint"] * (w2 - w1)) * N.z),
        (R2, -c["coupler_joint"] * (w2 - w1) * N.z),
        # the reactions, Newton's third law at each pin
        (O, Ox * N.x + Oy * N.y),
        (A2, Ax * N.x + Ay * N.y), (A1, -Ax * N.x - Ay * N.y),
        (B3, Bx * N.x + By * N.y + N3 * N.y), (B2, -Bx * N.x - By * N.y),
        (C4, N4 * N.y),
    ]
    kane = me.KanesMethod(N, q_ind=[q1, q2], u_ind=[u1, u2],
                          kd_eqs=[q1.diff() - u1, q2.diff() - u2], u_auxiliary=list(ua))
    kane.kanes_equations(bodies, loads)
    udot = sp.symbols("u1d u2d")
    aux = kane.auxiliary_eqs.subs({u1.diff(): udot[0], u2.diff(): udot[1]})
    states = [q1, q2, u1, u2]
    A_mat, b_vec = sp.linear_eq_to_matrix(list(aux), list(lam))
    coefficients = sp.lambdify(states, A_mat, "numpy")
    rhs = sp.lambdify(states + list(udot) + [torque], b_vec, "numpy")
    mass = sp.lambdify(states, kane.mass_matrix, "numpy")
    forcing = sp.lambdify(states + [torque], kane.forcing, "numpy")

    def reactions(state, m_m):
        u_dot = np.linalg.solve(np.asarray(mass(*state), float),
                                np.asarray(forcing(*state, m_m), float)).ravel()
        values = np.linalg.solve(np.asarray(coefficients(*state), float),
                                 np.asarray(rhs(*state, *u_dot, m_m), float)).ravel()
        return dict(zip(REACTIONS, values))

    return reactions
