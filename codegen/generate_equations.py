#!/usr/bin/python3
"""Derives the textbook example's mechanism (Kane equations - Example 1) with SymPy's
KanesMethod and writes the equations of motion as plain C++ (common subexpressions eliminated):
include/kane_sim/model/generated_equations.h, the fast path the integrators step.

Every parameter stays a symbol, so one generated header serves every config: the masses, L, I,
k, g, the spring's rest separation, the five dampers (four joints, one beside the spring) and the
applied driver moment M_m
(the motor line, a piecewise function of u1, limits M_m before it enters; contact acts by
impulses between steps). The generic Kane assembly (src/model/mechanism_model.cpp) remains the
readable reference and the tests' oracle. This derivation is the generator, not a test: the
SymPy oracle of the tests (test/tools/sympy_model.py) is a second derivation written apart on
purpose, so that a mistake here cannot pass its own check.

Usage (regenerate after changing the derivation; test/tools/codegen_test.sh fails otherwise):
    codegen/generate_equations.py [OUTPUT]       (default: the header above)
    codegen/generate_equations.py --check FILE   (exit 1 if FILE differs from a fresh derivation)
Debian 12's python3-sympy (1.11) generated the committed header.
"""
import argparse
import os
import sys

import sympy as sp
import sympy.physics.mechanics as me
from sympy.printing.cxx import CXX11CodePrinter
from sympy.printing.precedence import PRECEDENCE

HERE = os.path.dirname(os.path.abspath(__file__))
DEFAULT_OUTPUT = os.path.normpath(
    os.path.join(HERE, "..", "include", "kane_sim", "model", "generated_equations.h"))

# Parameter symbols, in the order of kane_sim::generated::Constants' fields: (symbol, C++ field,
# comment). The textbook's symbols where it has them.
PARAMETERS = [
    ("m", "rod_mass", "m [kg], each rod"),
    ("L", "rod_half_length", "L [m], the rods are 2L long"),
    ("I", "rod_inertia", "I1z = I2z [kg m^2], each rod about its center"),
    ("M1", "slider3_mass", "M1 [kg], slider 3 at B"),
    ("M2", "slider4_mass", "M2 [kg], slider 4 at C"),
    ("k", "spring_stiffness", "k [N/m]"),
    ("g", "gravity", "g [m/s^2], along +i (down)"),
    ("s0", "spring_rest_length", "x_C0 - x_B0 [m]: the spring is unstretched at this separation"),
    ("c_O", "crank_damping", "c_O [N m s/rad], pin O"),
    ("c_A", "coupler_damping", "c_A [N m s/rad], pin A"),
    ("c_B", "slider3_damping", "c_B [N s/m], slider 3 on the rail"),
    ("c_C", "slider4_damping", "c_C [N s/m], slider 4 on the rail"),
    ("c_S", "spring_damping", "c_S [N s/m], beside the spring between the sliders"),
]


def derive():
    """The mechanism in KanesMethod's vocabulary: frames, points, bodies, loads. Returns the
    symbols and (u', dissipated power) as expressions of q1, q2, u1, u2, M_m and the parameters."""
    q1, q2, u1, u2 = me.dynamicsymbols("q1 q2 u1 u2")
    p = {name: sp.Symbol(name, real=True) for name, _, _ in PARAMETERS}
    m, L, I, M1, M2, k, g, s0 = (p[n] for n in ("m", "L", "I", "M1", "M2", "k", "g", "s0"))
    M_m = sp.Symbol("M_m", real=True)  # the driver moment applied to rod 1 [N m]

    # Frame (0): i (N.x) points down, gravity along +i; rod 1 turns by q1 about k, rod 2 by -q1.
    N = me.ReferenceFrame("N")
    R1 = N.orientnew("R1", "Axis", [q1, N.z])
    R2 = N.orientnew("R2", "Axis", [-q1, N.z])
    R1.set_ang_vel(N, u1 * N.z)  # ω10 = u1 k
    R2.set_ang_vel(N, -u1 * N.z)  # ω20 = -u1 k
    O = me.Point("O")
    O.set_vel(N, 0)
    A = O.locatenew("A", 2 * L * R1.x)
    C1 = O.locatenew("C1", L * R1.x)
    C2 = A.locatenew("C2", L * R2.x)
    B = O.locatenew("B", 4 * L * sp.cos(q1) * N.x)  # slider 3 on the i axis
    C = O.locatenew("C", q2 * N.x)  # slider 4
    kinematic = {q1.diff(): u1, q2.diff(): u2}
    for point in (A, C1, C2, B, C):
        point.set_vel(N, point.pos_from(O).dt(N).subs(kinematic))

    bodies = [
        me.RigidBody("rod1", C1, R1, m, (me.inertia(R1, 0, 0, I), C1)),
        me.RigidBody("rod2", C2, R2, m, (me.inertia(R2, 0, 0, I), C2)),
        me.Particle("slider3", B, M1),
        me.Particle("slider4", C, M2),
    ]
    # Eq (15): e = (x_B - x_C) - (x_B0 - x_C0) > 0 compressed; F_eB = -k e i, F_eC = +k e i.
    e = (B.pos_from(O).dot(N.x) - q2) + s0
    w1, w2 = R1.ang_vel_in(N).dot(N.z), R2.ang_vel_in(N).dot(N.z)
    dampers = [
        (R1, -p["c_O"] * w1 * N.z),  # pin O on rod 1
        (R2, -p["c_A"] * (w2 - w1) * N.z),  # pin A on rod 2 ...
        (R1, p["c_A"] * (w2 - w1) * N.z),  # ... and its reaction on rod 1
        (B, -p["c_B"] * B.vel(N)),
        (C, -p["c_C"] * C.vel(N)),
        (C, -p["c_S"] * (C.vel(N) - B.vel(N))),  # beside the spring: on slider 4 ...
        (B, p["c_S"] * (C.vel(N) - B.vel(N))),  # ... and the opposite on slider 3
    ]
    loads = [
        (C1, m * g * N.x),  # eq (14): G1 ... G4
        (C2, m * g * N.x),
        (B, M1 * g * N.x),
        (C, M2 * g * N.x),
        (B, -k * e * N.x),  # eq (15)
        (C, k * e * N.x),
        (R1, M_m * N.z),  # the driver moment
    ] + dampers

    kane = me.KanesMethod(N, q_ind=[q1, q2], u_ind=[u1, u2], kd_eqs=[q1.diff() - u1, q2.diff() - u2])
    kane.kanes_equations(bodies, loads)
    # F*_r + F_r = 0 as M u' = f: solved symbolically (M is 2 x 2; LU keeps it short).
    u_dot = kane.mass_matrix.LUsolve(kane.forcing)
    speeds = {u1: sp.Symbol("u1"), u2: sp.Symbol("u2")}
    coords = {q1: sp.Symbol("q1"), q2: sp.Symbol("q2")}
    # The dampers' power, -Σ F · v >= 0, for the energy ledger's D'.
    power = 0
    for where, load in dampers:
        velocity = where.ang_vel_in(N) if isinstance(where, me.ReferenceFrame) else where.vel(N)
        power -= load.dot(velocity)
    # Simplified (cos^2 = 1 - sin^2 shortens M11), then any sin 2q1 that simplify() folds
    # written back as 2 sin q1 cos q1: one sincos serves the whole kernel.
    q1s = sp.Symbol("q1")
    plain = []
    for ex in list(u_dot) + [power]:
        ex = sp.simplify(ex.subs(speeds).subs(coords))
        ex = ex.subs(sp.cos(q1s) ** 2, 1 - sp.sin(q1s) ** 2)
        ex = ex.replace(lambda e: e.func in (sp.sin, sp.cos) and e.args[0] != q1s,
                        lambda e: sp.expand_trig(e))
        plain.append(sp.factor_terms(sp.expand(ex)))
    return p, M_m, plain


class _Printer(CXX11CodePrinter):
    """C++ with small integer powers as products (std::pow(x, 2) costs a call at -O2 without
    -ffast-math only for non-integer exponents, but x*x reads plainly and is exact)."""

    def _print_Pow(self, expr):
        base, exp = expr.as_base_exp()
        if exp.is_Integer and 2 <= exp <= 4:
            factor = self.parenthesize(base, PRECEDENCE["Mul"])
            return "*".join([factor] * int(exp))
        if exp == -1:
            return "1.0/%s" % self.parenthesize(base, PRECEDENCE["Mul"])
        return super()._print_Pow(expr)


def to_cpp(expr):
    return _Printer().doprint(expr)


DAMPERS = tuple(name for name, _, _ in PARAMETERS if name.startswith("c_"))  # the c_X above


def render_function(out, name, p, M_m, rates, skipped=()):
    """One inline C++ function template returning RatesOf<Real>; `skipped` parameters are zero
    in this variant (the caller guarantees it) and not read."""
    # sin q1 and cos q1 as two named inputs of the common subexpressions, computed by one
    # Trig<Real>::sinCos call.
    q1 = sp.Symbol("q1")
    sin_q1, cos_q1 = sp.Symbol("sin_q1"), sp.Symbol("cos_q1")
    rates = [ex.subs({sp.sin(q1): sin_q1, sp.cos(q1): cos_q1}) for ex in rates]
    rates = [ex.subs({p[n]: 0 for n in skipped}) for ex in rates]
    replacements, (e1, e2, ep) = sp.cse(rates, symbols=sp.numbered_symbols("t"),
                                        optimizations="basic")
    used = set().union(*(ex.free_symbols for _, ex in replacements), e1.free_symbols,
                       e2.free_symbols, ep.free_symbols)
    out("template <class Real, class SinCos = Trig<Real>>")
    out("inline RatesOf<Real> %s(const ConstantsOf<Real>& p, Real q1, Real q2, Real u1, Real u2,"
        % name)
    out(" " * len("inline RatesOf<Real> %s(" % name) + "Real M_m) {")
    for param, field, _ in PARAMETERS:
        if p[param] in used:
            out("  const Real %s = p.%s;" % (param, field))
    for arg in ("q2", "u1", "u2"):
        if sp.Symbol(arg) not in used:
            out("  static_cast<void>(%s);" % arg)
    if M_m not in used:
        out("  static_cast<void>(M_m);")
    out("  Real sin_q1, cos_q1;")
    out("  SinCos::sinCos(q1, &sin_q1, &cos_q1);")
    for symbol, ex in replacements:
        out("  const Real %s = %s;" % (symbol, to_cpp(ex)))
    out("  return {%s," % to_cpp(e1))
    out("          %s," % to_cpp(e2))
    out("          %s};" % to_cpp(ep))
    out("}")


def render():
    p, M_m, rates = derive()
    lines = []
    out = lines.append
    out("// GENERATED by codegen/generate_equations.py from a SymPy %s KanesMethod derivation of the"
        % sp.__version__)
    out("// textbook example's mechanism. Do not edit: change the script and regenerate")
    out("// (doc/theory/equations.md, \"Generated equations\"); test/tools/codegen_test.sh")
    out("// fails when they differ.")
    out("#ifndef KANE_SIM_MODEL_GENERATED_EQUATIONS_H")
    out("#define KANE_SIM_MODEL_GENERATED_EQUATIONS_H")
    out("")
    out("#include <cmath>")
    out("")
    out("namespace kane_sim {")
    out("namespace generated {")
    out("")
    out("// Every function below is a template over its number type Real: double for one mechanism,")
    out("// a SIMD batch of doubles for several stepped together (batch/lane_kernel.h): one text of")
    out("// the equations for both.")
    out("")
    out("// The parameters, runtime inputs (one header serves every config).")
    out("template <class Real>")
    out("struct ConstantsOf {")
    width = max(len(field) for _, field, _ in PARAMETERS)
    for name, field, comment in PARAMETERS:
        out("  Real %s;%s  // %s" % (field, " " * (width - len(field)), comment))
    out("};")
    out("using Constants = ConstantsOf<double>;")
    out("")
    out("// u1', u2' of F*_r + F_r = 0 (eq 18) and the dampers' dissipated power [W] at (q, u) under")
    out("// the applied driver moment M_m [N m].")
    out("template <class Real>")
    out("struct RatesOf {")
    out("  Real u1_dot;")
    out("  Real u2_dot;")
    out("  Real dissipated_power;")
    out("};")
    out("using Rates = RatesOf<double>;")
    out("")
    out("// sin q1 and cos q1 in one call: libm's sincos for double (GCC and Clang fuse std::sin and")
    out("// std::cos of one argument only sometimes once inlined into an integrator's stages). A SIMD")
    out("// batch type passes its own as the functions' SinCos (libm's per lane, or a vector sincos).")
    out("template <class Real>")
    out("struct Trig;")
    out("template <>")
    out("struct Trig<double> {")
    out("  static void sinCos(double x, double* s, double* c) { __builtin_sincos(x, s, c); }")
    out("};")
    out("")
    out("// Every term: the five dampers included.")
    render_function(out, "rates", p, M_m, rates)
    out("")
    out("// The same with the five dampers zero (the textbook's model; the dissipated power is 0):")
    out("// fewer terms where no damper is configured. Only for Constants whose dampers are all 0.")
    render_function(out, "ratesUndamped", p, M_m, rates, skipped=DAMPERS)
    out("")
    out("}  // namespace generated")
    out("}  // namespace kane_sim")
    out("")
    out("#endif  // KANE_SIM_MODEL_GENERATED_EQUATIONS_H")
    return "\n".join(lines) + "\n"


# The SymPy that generated the committed header: another version orders and names the common
# subexpressions differently (the same equations, another text), so --check would differ.
COMMITTED_WITH_SYMPY = "1.11"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("output", nargs="?", default=DEFAULT_OUTPUT)
    parser.add_argument("--check", metavar="FILE", nargs="+",
                        help="compare each FILE with one fresh derivation (exit 1 if any differs)")
    args = parser.parse_args()
    text = render()
    if args.check:
        differs = 0
        for path in args.check:
            with open(path) as f:
                if f.read() == text:
                    print("%s matches the derivation (SymPy %s)" % (path, sp.__version__))
                    continue
            differs += 1
            sys.stderr.write("%s differs from a fresh derivation (SymPy %s); regenerate with "
                             "codegen/generate_equations.py\n" % (path, sp.__version__))
        if differs and not sp.__version__.startswith(COMMITTED_WITH_SYMPY):
            sys.stderr.write(
                "note: this is SymPy %s from %s (%s); the committed header was "
                "generated with SymPy %s, Debian 12's python3-sympy: run it with "
                "/usr/bin/python3\n" % (sp.__version__, sys.executable,
                                         os.path.dirname(sp.__file__), COMMITTED_WITH_SYMPY))
        return 1 if differs else 0
    with open(args.output, "w") as f:
        f.write(text)
    print("wrote %s" % args.output)
    return 0


if __name__ == "__main__":
    sys.exit(main())
