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

The mechanism's parameters come from codegen/parameters.yaml, their one table; from it this
script also writes MechanismParameters (include/kane_sim/model/mechanism_parameters.h) and the
config schema's rows (src/config/mechanism_parameter_rows.cpp).

It also writes the rates' exact derivatives, d(u1', u2')/d(q1, q2, u1, u2, M_m), into
include/kane_sim/model/generated_jacobian.h (analyze, design and the rk4 stability check).

Usage (regenerate after changing the derivation or the table; test/tools/codegen_test.sh fails
otherwise):
    codegen/generate_equations.py                (writes the four generated files)
    codegen/generate_equations.py --check [FILE ...]
        (exit 1 if a generated file, or FILE against the generated file of its name, differs)
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
JACOBIAN_OUTPUT = os.path.normpath(
    os.path.join(HERE, "..", "include", "kane_sim", "model", "generated_jacobian.h"))

# The mechanism's parameters: codegen/parameters.yaml, the one table that names them (read by
# parameter_table.py, which also writes MechanismParameters and the schema's rows from it).
sys.path.insert(0, HERE)
import parameter_table  # noqa: E402

GROUPS, ROWS = parameter_table.load()
# Not a parameter: the model's own constant (MechanismModel's, from the initial configuration).
SPRING_REST = ("s0", "spring_rest_length",
               "s0 = x_C0 - x_B0 [m]: the spring is unstretched at this separation",
               "spring_rest_length")


def parameters():
    """(symbol, C++ field, comment, source) of each constant of the equations, in the order of
    kane_sim::generated::Constants' fields: the table's rows in the equations, then s0."""
    return parameter_table.equation_parameters(ROWS) + [SPRING_REST]


# The loads, one named list as `kanes_equations(bodies, loads)` takes them: every load's name,
# the kind of load it is, and for a load at a site (a resistance opposing a joint's rate, or a
# conservative load pulling a joint's coordinate back to its rest) its site, its law and its
# coefficient's symbol (and an elastic law's rest). The C++ model (LoadName, kLoadInfo) and
# every per-load output (powers, potential energies, the ledger) derive from this table through
# the generated header; a load at a site needs nothing else (MechanismModel::loads() and
# energy() apply any site's law). To add one: a row here, its parameters' rows in
# codegen/parameters.yaml, regenerate.
#   site: where it acts, on which rate and coordinate (sites in derive()); law: LAWS below.
#   A conservative load's potential energy is its law's (POTENTIALS); the derivation proves
#   that its generalized forces are -dV/dq_r and stops otherwise.
LOADS = [
    # name,             kind,           site,      law,       coefficient, rest
    ("gravity",         "gravity",      None,      None,      None,  None),  # eq (14): G1 ... G4
    ("spring",          "spring",       None,      None,      None,  None),  # eq (15): F_eB, F_eC
    ("motor",           "motor",        None,      None,      None,  None),  # M_m k on rod 1
    ("crank_damper",    "resistance",   "crank",   "viscous", "c_O", None),
    ("coupler_damper",  "resistance",   "coupler", "viscous", "c_A", None),
    ("slider3_damper",  "resistance",   "slider3", "viscous", "c_B", None),
    ("slider4_damper",  "resistance",   "slider4", "viscous", "c_C", None),
    ("spring_damper",   "resistance",   "spring",  "viscous", "c_S", None),
    ("contact",         "contact",      None,      None,      None,  None),  # N at C, -N at B
    ("crank_friction",  "resistance",   "crank",   "coulomb", "F_O", None),
    ("coupler_friction", "resistance",  "coupler", "coulomb", "F_A", None),
    ("slider3_friction", "resistance",  "slider3", "coulomb", "F_B", None),
    ("slider4_friction", "resistance",  "slider4", "coulomb", "F_C", None),
    ("crank_spring",    "conservative", "crank",   "elastic", "k_t", "q1_0"),
]
# The potential energy [J] of the loads that are not at a site, as the CSV and the message name
# it; a conservative load at a site has <name>_energy.
ENERGY_COLUMNS = {"gravity": "gravitational_energy", "spring": "spring_energy"}
# A law: the magnitude F its load opposes the site's rate v (a resistance) or its coordinate's
# distance from rest x - x0 (elastic) with, from its coefficient c (p: the parameter symbols).
# In order of cost: the generated rates come in one variant per prefix of this list (none; the
# viscous ones; ...; every law), and a config runs the shortest that holds the laws of its
# non-zero coefficients, so a law whose coefficients are all zero costs nothing and changes no
# bit. Coulomb friction is smoothed by tanh: no stiction (a held load creeps at v ~ v_s F / F_c).
LAWS = {
    "viscous": lambda c, v, x, x0, p: c * v,
    "coulomb": lambda c, v, x, x0, p: c * sp.tanh(v / p["v_s"]),
    "elastic": lambda c, v, x, x0, p: c * (x - x0),
}
# A conservative law's potential energy V(x) [J]; its force is -dV/dx, proved in derive().
POTENTIALS = {
    "elastic": lambda c, x, x0: c * (x - x0) ** 2 / 2,
}


def law_scale(law):
    """The parameter a law has of its own beyond its coefficient and rest (friction's v_s: the
    rate over which tanh bends), or None. A difference quotient's speed step must stay well inside
    it (stability's and analyze's Jacobians); a larger one softens the law (the stiffness check's
    advice)."""
    c, v, x, x0 = sp.symbols("c v x x0", real=True)
    p = {name: sp.Symbol(name, real=True) for name, *_ in parameters()}
    own = sorted(str(s) for s in LAWS[law](c, v, x, x0, p).free_symbols - {c, v, x, x0})
    if len(own) > 1:
        sys.exit("law %s has more than one parameter of its own (%s): one scale per law"
                 % (law, ", ".join(own)))
    return own[0] if own else None


def conservative(law):
    return law in POTENTIALS


def check_loads():
    """A conservative load declares its energy through its law, a resistance has none: a row
    that breaks this stops the generator, naming it (a forgotten energy would otherwise leave
    total_energy, the ledger and every energy consumer silently wrong)."""
    for name, kind, site, law, coefficient, rest in LOADS:
        if kind == "conservative" and not conservative(law):
            sys.exit("load %s is conservative, but its law %r declares no potential energy "
                     "(add it to POTENTIALS)" % (name, law))
        if kind == "resistance" and conservative(law):
            sys.exit("load %s is a resistance, but its law %r has a potential energy: make it "
                     "conservative" % (name, law))
        if bool(site) != bool(law and coefficient):
            sys.exit("load %s: a load at a site names its law and coefficient, others neither"
                     % name)


def variants():
    """(C++ enumerator, function name, laws kept): none, then each prefix of LAWS; the last,
    every term, is `rates`."""
    laws = list(LAWS)
    out = [("kUndamped", "ratesUndamped", ())]
    for i, law in enumerate(laws):
        name = "rates" if i == len(laws) - 1 else "rates" + law.capitalize()
        out.append(("k" + law.capitalize(), name, tuple(laws[:i + 1])))
    return out


def derive():
    """The mechanism in KanesMethod's vocabulary: frames, points, bodies, loads. Returns the
    symbols, (u', dissipated power) as expressions of q1, q2, u1, u2, M_m and the parameters
    with the viscous resistances only, and for each other law what its loads add to them."""
    q1, q2, u1, u2 = me.dynamicsymbols("q1 q2 u1 u2")
    p = {name: sp.Symbol(name, real=True) for name, *_ in parameters()}
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
    # Each site: its rate v, its coordinate x (v = x') and the entries of a load -F there (a
    # torque on a rod's frame, or a force at a slider's point, and the reaction where there is
    # one), F the law's magnitude.
    x_b = B.pos_from(O).dot(N.x)
    sites = {
        "crank": (w1, q1, lambda F: [(R1, -F * N.z)]),  # pin O on rod 1
        "coupler": (w2 - w1, -2 * q1,  # pin A, rod 2 on rod 1
                    lambda F: [(R2, -F * N.z), (R1, F * N.z)]),
        "slider3": (B.vel(N).dot(N.x), x_b, lambda F: [(B, -F * N.x)]),
        "slider4": (C.vel(N).dot(N.x), q2, lambda F: [(C, -F * N.x)]),
        "spring": ((C.vel(N) - B.vel(N)).dot(N.x), q2 - x_b,
                   lambda F: [(C, -F * N.x), (B, F * N.x)]),
    }
    # The viscous resistances enter the derivation; the other laws' generalized forces are
    # added to its result (below), law by law: simplify() with tanh terms takes tens of minutes,
    # and each variant without a law keeps the text, hence the bits, it had before that law.
    resistances, by_law, potentials = [], {}, []
    for name, kind, site, law, coefficient, rest in LOADS:
        if not site:
            continue
        rate, coordinate, entries = sites[site]
        x0 = p[rest] if rest else None
        load = entries(LAWS[law](p[coefficient], rate, coordinate, x0, p))
        (resistances if law == "viscous" else by_law.setdefault(law, [])).extend(load)
        if conservative(law):
            potentials.append((name, load, POTENTIALS[law](p[coefficient], coordinate, x0)))
    loads = [
        (C1, m * g * N.x),  # eq (14): G1 ... G4
        (C2, m * g * N.x),
        (B, M1 * g * N.x),
        (C, M2 * g * N.x),
        (B, -k * e * N.x),  # eq (15)
        (C, k * e * N.x),
        (R1, M_m * N.z),  # the driver moment
    ] + resistances

    kane = me.KanesMethod(N, q_ind=[q1, q2], u_ind=[u1, u2], kd_eqs=[q1.diff() - u1, q2.diff() - u2])
    kane.kanes_equations(bodies, loads)
    # F*_r + F_r = 0 as M u' = f: solved symbolically (M is 2 x 2; LU keeps it short).
    u_dot = kane.mass_matrix.LUsolve(kane.forcing)
    speeds = {u1: sp.Symbol("u1"), u2: sp.Symbol("u2")}
    coords = {q1: sp.Symbol("q1"), q2: sp.Symbol("q2")}
    def velocity(where):
        return where.ang_vel_in(N) if isinstance(where, me.ReferenceFrame) else where.vel(N)

    # The resistances' power, -Σ F · v >= 0, for the energy ledger's D'.
    power = 0
    for where, load in resistances:
        power -= load.dot(velocity(where))
    u, q = [u1, u2], [q1, q2]

    def active(entries):  # F_r = Σ F · ∂v/∂u_r (eq 16)
        return sp.Matrix([sum((load.dot(velocity(where).diff(u_r, N)) for where, load in entries),
                              sp.S.Zero) for u_r in u])

    # A conservative load's declared energy is its forces' own: F_r = -∂V/∂q_r (q_r' = u_r).
    for name, entries, V in potentials:
        for F_r, q_r in zip(active(entries), q):
            if sp.simplify(F_r + V.diff(q_r)) != 0:
                sys.exit("load %s: its potential energy %s does not give its forces (F_%s + "
                         "dV/d%s = %s)" % (name, V, q_r, q_r, sp.simplify(F_r + V.diff(q_r))))
    # Simplified (cos^2 = 1 - sin^2 shortens M11), then any sin 2q1 that simplify() folds
    # written back as 2 sin q1 cos q1: one sincos serves the whole kernel.
    q1s = sp.Symbol("q1")

    def plain(ex, simplify=True):
        ex = ex.subs(speeds).subs(coords)
        ex = sp.simplify(ex) if simplify else sp.cancel(ex)
        ex = ex.subs(sp.cos(q1s) ** 2, 1 - sp.sin(q1s) ** 2)
        ex = ex.replace(lambda e: e.func in (sp.sin, sp.cos) and e.args[0] != q1s,
                        lambda e: sp.expand_trig(e))
        return sp.factor_terms(sp.expand(ex))

    viscous = [plain(ex) for ex in list(u_dot) + [power]]
    # Each other law's loads: their generalized active forces through the same mass matrix, and
    # their dissipated power (none for a conservative law: its power is -dV/dt, not D').
    added = {}
    for law, entries in by_law.items():
        law_power = sp.S.Zero if conservative(law) else -sum(
            (load.dot(velocity(where)) for where, load in entries), sp.S.Zero)
        added[law] = [plain(ex, simplify=False)
                      for ex in list(kane.mass_matrix.LUsolve(active(entries))) + [law_power]]
    return p, M_m, viscous, added


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

    def _print_tanh(self, expr):
        # Through the math policy: libm's tanh for double and, lane by lane, for SIMD batches.
        return "MathOf::tanh(%s)" % self._print(expr.args[0])


def to_cpp(expr):
    return _Printer().doprint(expr)


def coefficients(laws):
    """The coefficient symbols of the loads at a site obeying `laws`."""
    return tuple(c for _, _, site, law, c, _ in LOADS if site and law in laws)


# What a rate depends on besides the constants: the state's functions the kernel computes.
def state_symbols(M_m):
    return [sp.Symbol(n) for n in ("sin_q1", "cos_q1", "q2", "u1", "u2")] + [M_m]


def separate_constants(rates, state):
    """Each rate as a polynomial in the state (sin q1, cos q1, q2, u1, u2, M_m, and each tanh of
    one) over a polynomial in it, nested by Horner's rule, whose coefficients are functions of
    the constants alone, each named once (a0, a1, ...): the coefficients are the same at every
    stage of a step, so the integrator forms them once per step instead of the state's terms
    forming them again at each stage. A denominator free of the state (u2' = .../M2) goes into
    the coefficients: no division at the stages. Returns (rates, [(name, coefficient)])."""
    named = {}

    def name(coefficient):
        if coefficient.is_Number:
            return coefficient
        if coefficient not in named:
            named[coefficient] = sp.Symbol("a%d" % len(named))
        return named[coefficient]

    def polynomial(ex, variables, divisor=sp.S.One):
        terms = sp.Poly(sp.expand(ex), *variables).terms()
        sum_ = sp.Add(*[name(sp.factor_terms(coefficient / divisor)) *
                        sp.Mul(*[v ** n for v, n in zip(variables, powers)])
                        for powers, coefficient in terms])
        return sp.horner(sum_, *variables) if sum_.free_symbols & set(variables) else sum_

    def form(ex):
        # tanh's argument is a rate too; inside ex each tanh stands as one more variable.
        ex = ex.replace(lambda e: isinstance(e, sp.tanh), lambda e: sp.tanh(form(e.args[0])))
        tanhs = {t: sp.Dummy() for t in sorted(ex.atoms(sp.tanh), key=sp.default_sort_key)}
        variables = state + list(tanhs.values())
        numerator, denominator = sp.fraction(sp.together(ex.subs(tanhs)))
        if denominator.free_symbols & set(variables):
            ex = polynomial(numerator, variables) / polynomial(denominator, variables)
        else:
            ex = polynomial(numerator, variables, denominator)
        return ex.subs({d: t for t, d in tanhs.items()})

    rates = [form(ex) for ex in rates]
    return rates, [(symbol, coefficient) for coefficient, symbol in named.items()]


def render_function(out, name, p, M_m, rates, skipped=()):
    """One inline C++ function template returning RatesOf<Real>; `skipped` parameters are zero
    in this variant (the caller guarantees it) and not read."""
    # sin q1 and cos q1 as two named inputs of the common subexpressions, computed by one
    # Math<Real>::sinCos call.
    q1 = sp.Symbol("q1")
    sin_q1, cos_q1 = sp.Symbol("sin_q1"), sp.Symbol("cos_q1")
    rates = [ex.subs({sp.sin(q1): sin_q1, sp.cos(q1): cos_q1}) for ex in rates]
    rates = [ex.subs({p[n]: 0 for n in skipped}) for ex in rates]
    # q1 itself is a term of the state only where an elastic law at the crank puts it.
    state = state_symbols(M_m)
    if any(q1 in ex.free_symbols for ex in rates):
        state.append(q1)
    rates, coefficients = separate_constants(rates, state)
    constant_terms, named = sp.cse([c for _, c in coefficients], symbols=sp.numbered_symbols("t"),
                                   optimizations="basic")
    # Each tanh a named value, taken two at a time (MathOf::tanhPair: one two-lane call of the
    # library costs what one value does).
    tanhs = sorted({t for ex in rates for t in ex.atoms(sp.tanh)}, key=sp.default_sort_key)
    tanh_values = [sp.Symbol("tanh_%d" % i) for i in range(len(tanhs))]
    rates = [ex.subs(dict(zip(tanhs, tanh_values))) for ex in rates]
    replacements, (e1, e2, ep) = sp.cse(rates, symbols=sp.numbered_symbols("e"),
                                        optimizations="basic")
    used = set().union(*(ex.free_symbols for _, ex in constant_terms),
                       *(ex.free_symbols for ex in named))
    used_by_state = set().union(*(ex.free_symbols for _, ex in replacements), e1.free_symbols,
                                e2.free_symbols, ep.free_symbols)
    out("template <class Real, class MathOf = Math<Real>>")
    out("inline RatesOf<Real> %s(const ConstantsOf<Real>& p, Real q1, Real q2, Real u1, Real u2,"
        % name)
    out(" " * len("inline RatesOf<Real> %s(" % name) + "Real M_m) {")
    for param, field, *_ in parameters():
        if p[param] in used:
            out("  const Real %s = p.%s;" % (param, field))
    for arg in ("q2", "u1", "u2"):
        if sp.Symbol(arg) not in used_by_state:
            out("  static_cast<void>(%s);" % arg)
    if M_m not in used_by_state:
        out("  static_cast<void>(M_m);")
    out("  // The coefficients: the constants' alone, the same at every stage of a step.")
    for symbol, ex in constant_terms:
        out("  const Real %s = %s;" % (symbol, to_cpp(ex)))
    for (symbol, _), ex in zip(coefficients, named):
        out("  const Real %s = %s;" % (symbol, to_cpp(ex)))
    out("  // The state's terms.")
    render_state_math(out, tanhs, tanh_values)
    for symbol, ex in replacements:
        out("  const Real %s = %s;" % (symbol, to_cpp(ex)))
    out("  return {%s," % to_cpp(e1))
    out("          %s," % to_cpp(e2))
    out("          %s};" % to_cpp(ep))
    out("}")


def render_state_math(out, tanhs, tanh_values):
    """sin q1 and cos q1 by one Math<Real>::sinCos call, and each tanh a named value, taken two
    at a time (MathOf::tanhPair: one two-lane call of the library costs what one value does)."""
    out("  Real sin_q1, cos_q1;")
    out("  MathOf::sinCos(q1, &sin_q1, &cos_q1);")
    for i in range(0, len(tanhs) - 1, 2):
        out("  Real %s, %s;" % (tanh_values[i], tanh_values[i + 1]))
        out("  MathOf::tanhPair(%s, %s, &%s, &%s);" % (
            to_cpp(tanhs[i].args[0]), to_cpp(tanhs[i + 1].args[0]), tanh_values[i],
            tanh_values[i + 1]))
    if len(tanhs) % 2:
        out("  const Real %s = MathOf::tanh(%s);" % (tanh_values[-1], to_cpp(tanhs[-1].args[0])))


# The Jacobian's columns: the state x = (q1, q2, u1, u2), then the applied moment M_m.
JACOBIAN_COLUMNS = ("q1", "q2", "u1", "u2", "M_m")


def render_jacobian(derivation):
    """generated_jacobian.h: d(u1', u2')/d(q1, q2, u1, u2, M_m) of `rates` (every load at a site),
    the same SymPy expressions differentiated, their common subexpressions named once."""
    p, M_m, _, _ = derivation
    q1, sin_q1, cos_q1 = sp.Symbol("q1"), sp.Symbol("sin_q1"), sp.Symbol("cos_q1")
    variables = [q1, sp.Symbol("q2"), sp.Symbol("u1"), sp.Symbol("u2"), M_m]
    rates = full_rates(derivation)[:2]
    entries = [sp.diff(rate, v).subs({sp.sin(q1): sin_q1, sp.cos(q1): cos_q1})
               for rate in rates for v in variables]
    tanhs = sorted({t for ex in entries for t in ex.atoms(sp.tanh)}, key=sp.default_sort_key)
    tanh_values = [sp.Symbol("tanh_%d" % i) for i in range(len(tanhs))]
    entries = [ex.subs(dict(zip(tanhs, tanh_values))) for ex in entries]
    replacements, reduced = sp.cse(entries, symbols=sp.numbered_symbols("j"),
                                   optimizations="basic")
    used = set().union(*(ex.free_symbols for _, ex in replacements),
                       *(ex.free_symbols for ex in reduced),
                       *(t.args[0].free_symbols for t in tanhs))
    lines = []
    out = lines.append
    out("// GENERATED by codegen/generate_equations.py from a SymPy %s KanesMethod derivation of the"
        % sp.__version__)
    out("// textbook example's mechanism. Do not edit: change the script and regenerate")
    out("// (doc/theory/equations.md, \"Generated equations\"); test/tools/codegen_test.sh")
    out("// fails when they differ.")
    out("#ifndef KANE_SIM_MODEL_GENERATED_JACOBIAN_H")
    out("#define KANE_SIM_MODEL_GENERATED_JACOBIAN_H")
    out("")
    out("#include \"kane_sim/model/generated_equations.h\"")
    out("")
    out("namespace kane_sim {")
    out("namespace generated {")
    out("")
    out("// d(u1', u2')/d(%s): the derivatives of rates() (every load at a site, the" %
        ", ".join(JACOBIAN_COLUMNS))
    out("// applied driver moment M_m after the motor line), the derivation's own expressions")
    out("// differentiated symbolically: exact, not differences. Rows u1', u2'; columns in that order.")
    out("constexpr int kJacobianColumns = %d;" % len(JACOBIAN_COLUMNS))
    out("template <class Real>")
    out("struct RateJacobianOf {")
    out("  Real d[2][kJacobianColumns];")
    out("};")
    out("using RateJacobian = RateJacobianOf<double>;")
    out("")
    out("template <class Real, class MathOf = Math<Real>>")
    out("inline RateJacobianOf<Real> rateJacobian(const ConstantsOf<Real>& p, Real q1, Real q2,")
    out("                                         Real u1, Real u2, Real M_m) {")
    for param, field, *_ in parameters():
        if p[param] in used:
            out("  const Real %s = p.%s;" % (param, field))
    for arg in ("q1", "q2", "u1", "u2"):
        if sp.Symbol(arg) not in used and arg != "q1":
            out("  static_cast<void>(%s);" % arg)
    if M_m not in used:
        out("  static_cast<void>(M_m);")
    render_state_math(out, tanhs, tanh_values)
    for symbol, ex in replacements:
        out("  const Real %s = %s;" % (symbol, to_cpp(ex)))
    out("  RateJacobianOf<Real> jacobian;")
    for index, ex in enumerate(reduced):
        row, column = divmod(index, len(JACOBIAN_COLUMNS))
        out("  jacobian.d[%d][%d] = %s;  // d u%d'/d %s" % (
            row, column, to_cpp(ex), row + 1, JACOBIAN_COLUMNS[column]))
    out("  return jacobian;")
    out("}")
    out("")
    out("}  // namespace generated")
    out("}  // namespace kane_sim")
    out("")
    out("#endif  // KANE_SIM_MODEL_GENERATED_JACOBIAN_H")
    return "\n".join(lines) + "\n"


def render_loads(out):
    """The load table: LoadName and, per load, its name, kind, site, law, coefficient, rest and
    energy column."""
    out("// The loads, one named list (codegen/generate_equations.py's LOADS): each load's name, kind")
    out("// and, for a load at a site, where it acts, its law and its coefficient (an index into")
    out("// ConstantsOf's fields). Several entries of MechanismModel::loads() can share a name.")
    out("enum class LoadName {")
    for name, *_ in LOADS:
        out("  k%s," % "".join(w.capitalize() for w in name.split("_")))
    out("  kCount")
    out("};")
    out("constexpr int kNumLoadNames = static_cast<int>(LoadName::kCount);")
    kinds = list(dict.fromkeys(kind for _, kind, *_ in LOADS))
    out("enum class LoadKind { %s };" % ", ".join("k%s" % k.capitalize() for k in kinds))
    out("// Where a load at a site acts, its rate and its coordinate: the crank's pin O (w1 and q1, on")
    out("// rod 1), the coupler's pin A (w2 - w1 and -2 q1, on rod 2 and its reaction on rod 1), the")
    out("// sliders on the rail (v_B and x_B, v_C and x_C), the pair beside the spring (v_C - v_B and")
    out("// x_C - x_B, on slider 4 and the opposite on 3).")
    sites = ["crank", "coupler", "slider3", "slider4", "spring"]
    out("enum class LoadSite { kNone, %s };" % ", ".join("k%s" % x.capitalize() for x in sites))
    out("// The laws of codegen/generate_equations.py's LAWS (viscous: c v; coulomb: c tanh(v / v_s);")
    out("// elastic: c (x - x0), whose potential energy is c (x - x0)^2 / 2).")
    out("enum class LoadLaw { kNone, %s };" % ", ".join("k%s" % law.capitalize() for law in LAWS))
    out("struct LoadInfo {")
    out("  const char* name;   // snake_case: power column power_<name>, ...")
    out("  LoadKind kind;")
    out("  LoadSite site;      // loads at a site only")
    out("  LoadLaw law;        // loads at a site only")
    out("  int coefficient;    // at a site: the index of its coefficient among the constants")
    out("  const char* symbol; // at a site: that coefficient's symbol")
    out("  int rest;           // an elastic law: the index of its rest coordinate x0; else -1")
    out("  bool dissipative;   // its power is <= 0 and counts in the ledger's D'")
    out("  // A conservative load's potential energy column (CSV, Python; the message's")
    out("  // load_energies), or nullptr: its power is -d(that energy)/dt.")
    out("  const char* energy_column;")
    out("  // Its law's own scale of rate (friction's v_s: tanh bends within it), an index among the")
    out("  // constants, or -1.")
    out("  int rate_scale;")
    out("};")
    out("// Indexed by LoadName.")
    out("constexpr LoadInfo kLoadInfo[kNumLoadNames] = {")
    index = {name: i for i, (name, *_) in enumerate(parameters())}
    for name, kind, site, law, coefficient, rest in LOADS:
        energy = ENERGY_COLUMNS.get(name) or (name + "_energy" if conservative(law) else None)
        scale = law_scale(law) if law else None
        out('    {"%s", LoadKind::k%s, LoadSite::k%s, LoadLaw::k%s, %d, "%s", %d, %s, %s, %d},' % (
            name, kind.capitalize(), (site or "none").capitalize(), (law or "none").capitalize(),
            index[coefficient] if coefficient else -1, coefficient or "",
            index[rest] if rest else -1, "true" if kind == "resistance" else "false",
            '"%s"' % energy if energy else "nullptr", index[scale] if scale else -1))
    out("};")
    out("// The constants' symbols, in ConstantsOf's order (a schema row's equation symbol is one).")
    out("constexpr const char* kConstantSymbols[] = {%s};" % ", ".join(
        '"%s"' % n for n, *_ in parameters()))
    out("// Their config keys (codegen/parameters.yaml; \"\" for s0, the model's own).")
    keys = {r.equation_symbol: r.key for r in ROWS}
    out("constexpr const char* kConstantKeys[] = {%s};" % ", ".join(
        '"%s"' % keys.get(n, "") for n, *_ in parameters()))


def render_constants_source(out):
    """constantsFrom: every constant from MechanismParameters, in one generated function (no
    constant can be left unset)."""
    out("// Every constant from the mechanism's parameters (p: a MechanismParameters or anything")
    out("// with its members) and the spring's rest separation.")
    out("template <class Parameters>")
    out("Constants constantsFrom(const Parameters& p, double spring_rest_length) {")
    out("  Constants c;")
    for name, field, _, source in parameters():
        out("  c.%s = %s;  // %s" % (field, source, name))
    out("  return c;")
    out("}")


def full_rates(derivation):
    """u1', u2' and the dissipated power with every load at a site (the variant `rates`)."""
    _, _, viscous_rates, added = derivation
    return [sp.Add(v, *(added[law][i] for law in LAWS if law != "viscous"))
            for i, v in enumerate(viscous_rates)]


def render(derivation=None):
    """generated_equations.h's text from `derivation` (derive()'s; None: derived here)."""
    check_loads()
    p, M_m, viscous_rates, added = derivation or derive()
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
    out("#include <limits>")
    out("")
    out("#include \"kane_sim/model/math_functions.h\"")
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
    width = max(len(field) for _, field, *_ in parameters())
    for name, field, comment, _ in parameters():
        out("  Real %s;%s  // %s" % (field, " " * (width - len(field)), comment))
    out("};")
    out("using Constants = ConstantsOf<double>;")
    out("")
    render_constants_source(out)
    out("")
    render_loads(out)
    out("")
    out("// u1', u2' of F*_r + F_r = 0 (eq 18) and the resistances' dissipated power [W] at (q, u)")
    out("// under the applied driver moment M_m [N m].")
    out("template <class Real>")
    out("struct RatesOf {")
    out("  Real u1_dot;")
    out("  Real u2_dot;")
    out("  Real dissipated_power;")
    out("};")
    out("using Rates = RatesOf<double>;")
    out("")
    out("// The math the equations call: sin q1 and cos q1 in one call, and tanh for the laws that")
    out("// call it, two values a call; for double the one implementation every path uses")
    out("// (model/math_functions.h).")
    out("// A SIMD batch type passes its own as the functions' MathOf (the same functions' vector")
    out("// forms, src/batch/simd_lanes.h).")
    out("template <class Real>")
    out("struct Math;")
    out("template <>")
    out("struct Math<double> {")
    out("  static void sinCos(double x, double* s, double* c) { math::sinCos(x, s, c); }")
    out("  static double tanh(double x) { return math::tanh(x); }")
    out("  static void tanhPair(double x, double y, double* tx, double* ty) {")
    out("    math::tanhPair(x, y, tx, ty);")
    out("  }")
    out("};")
    out("")
    out("// Which variant a set of constants needs: each leaves out the terms of the laws after it in")
    out("// LAWS (their coefficients all zero): fewer terms, and the bits those terms' absence gives.")
    out("enum class RatesVariant { %s };" % ", ".join(e for e, _, _ in variants()))
    out("constexpr RatesVariant kRatesVariants[] = {%s};" % ", ".join(
        "RatesVariant::" + e for e, _, _ in variants()))
    out("constexpr RatesVariant kEveryTerm = RatesVariant::%s;  // rates()" % variants()[-1][0])
    for enumerator, name, laws in variants():
        out("")
        if len(laws) == len(LAWS):
            out("// Every term: the loads at a site of every law (%s)." % ", ".join(laws))
        elif laws:
            out("// The terms of the loads at a site whose law is %s; only for Constants whose"
                % " or ".join(laws))
            out("// other loads' coefficients are 0.")
        else:
            out("// No load at a site (every coefficient 0): the textbook's model; dissipated "
                "power 0.")
        source = [sp.Add(v, *(added[law][i] for law in laws if law != "viscous"))
                  for i, v in enumerate(viscous_rates)]
        skipped = coefficients(tuple(law for law in LAWS if law not in laws))
        render_function(out, name, p, M_m, source, skipped=skipped)
    out("")
    out("// The variant `constants` need: the shortest that keeps every non-zero load's law.")
    out("inline RatesVariant variantFor(const Constants& constants) {")
    out("  const double* value = &constants.%s;" % parameters()[0][1])
    out("  static_assert(sizeof(Constants) == %d * sizeof(double), \"Constants holds doubles\");"
        % len(parameters()))
    out("  int need = 0;  // LoadLaw's order is the variants' (kNone: kUndamped)")
    out("  for (const LoadInfo& load : kLoadInfo)")
    out("    if (load.site != LoadSite::kNone && value[load.coefficient] != 0.0 &&")
    out("        static_cast<int>(load.law) > need)")
    out("      need = static_cast<int>(load.law);")
    out("  return static_cast<RatesVariant>(need);")
    out("}")
    out("")
    out("// The smallest rate scale of the laws in use (a load at a site whose coefficient is not 0):")
    out("// its value and its constant's index, or infinity and -1 when no law in use has one.")
    out("struct RateScale {")
    out("  double value;")
    out("  int constant;")
    out("};")
    out("inline RateScale smallestRateScale(const Constants& constants) {")
    out("  const double* value = &constants.%s;" % parameters()[0][1])
    out("  RateScale smallest{std::numeric_limits<double>::infinity(), -1};")
    out("  for (const LoadInfo& load : kLoadInfo)")
    out("    if (load.rate_scale >= 0 && value[load.coefficient] != 0.0 &&")
    out("        !(value[load.rate_scale] >= smallest.value))")
    out("      smallest = {value[load.rate_scale], load.rate_scale};")
    out("  return smallest;")
    out("}")
    out("")
    out("// The rates by `variant` (the caller keeps it fixed over a run: the branch is predicted).")
    out("template <class Real, class MathOf = Math<Real>>")
    out("inline RatesOf<Real> ratesFor(RatesVariant variant, const ConstantsOf<Real>& p, Real q1,")
    out("                              Real q2, Real u1, Real u2, Real M_m) {")
    out("  switch (variant) {")
    for enumerator, name, laws in variants()[:-1]:
        out("    case RatesVariant::%s:" % enumerator)
        out("      return %s<Real, MathOf>(p, q1, q2, u1, u2, M_m);" % name)
    out("    default:")
    out("      break;")
    out("  }")
    out("  return rates<Real, MathOf>(p, q1, q2, u1, u2, M_m);")
    out("}")
    out("")
    out("}  // namespace generated")
    out("}  // namespace kane_sim")
    out("")
    out("#endif  // KANE_SIM_MODEL_GENERATED_EQUATIONS_H")
    return "\n".join(lines) + "\n"


# The SymPy that generated the committed header: another version orders and names the common
# subexpressions differently (the same equations, another text), so --check would differ.
COMMITTED_WITH_SYMPY = "1.11"


def outputs():
    """{path: text} of every generated file: the equations, and what the parameter table gives."""
    parameter_table.check(ROWS)
    check_loads()  # before the derivation: a load that declares no energy is named first
    derivation = derive()
    return {DEFAULT_OUTPUT: render(derivation),
            JACOBIAN_OUTPUT: render_jacobian(derivation),
            parameter_table.STRUCT_OUTPUT: parameter_table.render_struct(GROUPS, ROWS),
            parameter_table.ROWS_OUTPUT: parameter_table.render_rows(GROUPS, ROWS)}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", metavar="FILE", nargs="*",
                        help="compare each generated file (or each FILE, with the generated file "
                        "of its name) with a fresh derivation; exit 1 if any differs")
    args = parser.parse_args()
    texts = outputs()
    if args.check is not None:
        by_name = {os.path.basename(path): path for path in texts}
        differs = 0
        for path in args.check or list(texts):
            name = os.path.basename(path)
            if name not in by_name:
                sys.stderr.write("%s: not a generated file's name (%s)\n"
                                 % (path, ", ".join(sorted(by_name))))
                differs += 1
                continue
            with open(path) as f:
                if f.read() == texts[by_name[name]]:
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
    for path, text in texts.items():
        with open(path, "w") as f:
            f.write(text)
        print("wrote %s" % path)
    return 0


if __name__ == "__main__":
    sys.exit(main())
