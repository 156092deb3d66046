#!/usr/bin/python3
"""A load is one declaration, as far as the code generator goes, and a conservative load carries
its energy. Two throw-away loads are added to the generator's tables (a parameter row of
codegen/parameters.yaml's table, a LOADS row), nothing else:

- a resistance (one parameter row, one LOADS row) reaches MechanismParameters (its field, its
  default, fields(), any()), the schema's rows, and every part of the generated equations: the
  constants struct, constantsFrom(), LoadName, kLoadInfo (with its coefficient's index),
  kConstantSymbols and kConstantKeys, the full rates variant (and not the undamped one), and
  variantFor(); the header compiles and runs with g++: the coefficient changes u' of the full
  variant, and variantFor() picks that variant only when it is not 0;
- a conservative load (an elastic spring holding slider 4 at a rest position: two parameter
  rows, one LOADS row) gets its energy column in kLoadInfo and its force in the rates (u2' moves
  by exactly -k_T (q2 - x_T) / M2, no dissipated power); with its law's energy left out, or an
  energy whose gradient is not its force, the generator refuses it, naming the load.

(The C++ consumers beyond the header read kLoadInfo and the schema's roles:
test_generated_equations' every-parameter test, test_parameter_schema and test_constraint_forces'
power-flow test, where each conservative load's power must be -dV/dt, hold them to the tables.)
Usage: throwaway_load_test.py
"""
import contextlib
import importlib.util
import io
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
GENERATOR = os.path.join(HERE, "..", "..", "codegen", "generate_equations.py")

# What both programs start from (a C++ prelude).
PRELUDE = r"""
#include <cmath>
#include <cstdio>
#include "generated_equations.h"
using namespace kane_sim::generated;
// The shipped mechanism's constants, every load at a site off.
Constants shipped() {
  Constants c{};
  c.rod_mass = 1; c.rod_half_length = 0.25; c.rod_inertia = 0.02; c.slider3_mass = 0.5;
  c.slider4_mass = 0.8; c.spring_stiffness = 200; c.gravity = 9.81; c.spring_rest_length = 0.3;
  c.friction_velocity_scale = 0.01;
  return c;
}
// u' at one state under one torque, by the variant the constants need.
Rates at(const Constants& c) { return ratesFor(variantFor(c), c, 0.4, 1.2, 1.5, -0.7, 2.0); }
"""

DAMPER_PROGRAM = PRELUDE + r"""
int main() {
  Constants c = shipped();
  const RatesVariant off = variantFor(c);
  const Rates before = at(c);
  c.damping_throwaway = 3.0;
  const RatesVariant on = variantFor(c);
  const Rates after = at(c);
  const LoadInfo& load = kLoadInfo[static_cast<int>(LoadName::kThrowawayDamper)];
  std::printf("%d %d %d %s %d %d\n", static_cast<int>(off), static_cast<int>(on),
              after.u2_dot != before.u2_dot && after.dissipated_power > before.dissipated_power,
              load.name, load.coefficient, static_cast<int>(load.site == LoadSite::kSlider4));
  return 0;
}
"""

SPRING_PROGRAM = PRELUDE + r"""
int main() {
  Constants c = shipped();
  const Rates before = at(c);
  c.throwaway_stiffness = 30.0;
  c.throwaway_rest = 0.9;
  const Rates after = at(c);
  const double want = -30.0 * (1.2 - 0.9) / 0.8;  // slider 4 alone on q2: -k_T (q2 - x_T) / M2
  std::printf("%d %d %d\n", static_cast<int>(variantFor(c) == kEveryTerm),
              std::abs(after.u2_dot - before.u2_dot - want) < 1e-12 * 100,
              static_cast<int>(after.dissipated_power != before.dissipated_power));
  return 0;
}
"""


def generator():
    """A fresh copy of the code generator's module (each scenario edits its tables)."""
    spec = importlib.util.spec_from_file_location("generate_equations", GENERATOR)
    gen = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(gen)
    return gen


def compiled_output(text, program):
    """Compiles `program` against the header `text` and runs it: (its output's words, or None
    with the compiler's message)."""
    with tempfile.TemporaryDirectory() as work:
        with open(os.path.join(work, "generated_equations.h"), "w") as f:
            f.write(text)
        with open(os.path.join(work, "main.cpp"), "w") as f:
            f.write(program)
        exe = os.path.join(work, "main")
        # The package's headers after `work` (the math functions the header includes), SLEEF
        # for them.
        built = subprocess.run(["g++", "-std=c++17", "-O1", "-Wall", "-Werror", "-I", work,
                                "-I", os.path.join(HERE, "..", "..", "include"),
                                os.path.join(work, "main.cpp"), "-o", exe, "-lsleef"],
                               capture_output=True, text=True)
        if built.returncode != 0:
            return None, built.stderr[:2000]
        return subprocess.run([exe], capture_output=True, text=True).stdout.split(), ""


def report(ok, what):
    print("%s %s" % ("ok  " if ok else "FAIL", what))
    return 0 if ok else 1


def parameter(gen, key, symbol, role, doc):
    """A row of the parameter table, as codegen/parameters.yaml would give it."""
    gen.ROWS.append(gen.parameter_table.Row(
        {"key": key, "symbol": symbol, "unit": "", "rule": "non-negative" if role != "load shape"
         else "finite", "default": 0, "role": role, "doc": doc}, gen.GROUPS))


def a_resistance():
    gen = generator()
    # The declaration: a second viscous damper on slider 4, coefficient c_T.
    parameter(gen, "damping.throwaway", "c_T", "dissipative", "a throw-away damper")
    gen.LOADS.append(("throwaway_damper", "resistance", "slider4", "viscous", "c_T", None))
    text = gen.render()
    index = [name for name, *_ in gen.parameters()].index("c_T")
    checks = [
        ("the constants struct", "  Real damping_throwaway;"),
        ("constantsFrom()", "c.damping_throwaway = p.damping.throwaway;"),
        ("LoadName", "  kThrowawayDamper,"),
        ("kLoadInfo", '{"throwaway_damper", LoadKind::kResistance, LoadSite::kSlider4, '
                      'LoadLaw::kViscous, %d, "c_T", -1, true, nullptr, -1}' % index),
        ("kConstantSymbols", '"c_T", "s0"};'),
        ("kConstantKeys", '"damping.throwaway", ""};'),
    ]
    struct = gen.parameter_table.render_struct(gen.GROUPS, gen.ROWS)
    rows = gen.parameter_table.render_rows(gen.GROUPS, gen.ROWS)
    checks_elsewhere = [
        ("MechanismParameters' field and default", struct, "  double throwaway = 0.0;"),
        ("JointDamping::fields()", struct, "spring, throwaway); }"),
        ("JointDamping::any()", struct, "throwaway != 0.0;"),
        ("the schema's rows", rows,
         'row("damping", "throwaway", KANE_SIM_FIELD(mechanism.damping.throwaway)'),
        ("the schema row's role and symbol", rows, '.role(ParameterRole::kDissipative, "c_T")'),
    ]
    failures = sum(report(needle in text, "%s has the new damper" % what) for what, needle in checks)
    failures += sum(report(needle in where, "%s has the new damper" % what)
                    for what, where, needle in checks_elsewhere)
    full = text[text.index("inline RatesOf<Real> rates("):]
    undamped = text[text.index("inline RatesOf<Real> ratesUndamped("):
                    text.index("inline RatesOf<Real> ratesViscous(")]
    failures += report("const Real c_T = p.damping_throwaway;" in full and "c_T" not in undamped,
                       "the full rates read c_T, the undamped ones do not")
    out, error = compiled_output(text, DAMPER_PROGRAM)
    want = ["0", "1", "1", "throwaway_damper", str(index), "1"]
    failures += report(out == want, "compiled and ran: variant off/on, u2' and D' moved, name, "
                       "index, site: %s" % (" ".join(out) if out else error))
    return failures


def conservative_load(potential=True, wrong_potential=False):
    """A throw-away elastic spring holding slider 4 at x_T: coefficient k_T, rest x_T."""
    gen = generator()
    parameter(gen, "mechanism.throwaway_stiffness", "k_T", "stiffness", "a throw-away spring")
    parameter(gen, "mechanism.throwaway_rest", "x_T", "load shape", "its rest position")
    law = "elastic"
    if not potential:  # a new conservative law whose energy was left out
        law = "stiffening"
        gen.LAWS[law] = lambda c, v, x, x0, p: c * (x - x0) ** 3
    elif wrong_potential:  # a new conservative law whose energy is not its force's
        law = "stiffening"
        gen.LAWS[law] = lambda c, v, x, x0, p: c * (x - x0) ** 3
        gen.POTENTIALS[law] = lambda c, x, x0: c * (x - x0) ** 4 / 2
    gen.LOADS.append(("throwaway_spring", "conservative", "slider4", law, "k_T", "x_T"))
    return gen


def a_conservative_load():
    gen = conservative_load()
    text = gen.render()
    names = [name for name, *_ in gen.parameters()]
    k, x = names.index("k_T"), names.index("x_T")
    failures = report('{"throwaway_spring", LoadKind::kConservative, LoadSite::kSlider4, '
                      'LoadLaw::kElastic, %d, "k_T", %d, false, "throwaway_spring_energy", -1}'
                      % (k, x) in text, "kLoadInfo has the new spring, its rest and its energy "
                      "column")
    out, error = compiled_output(text, SPRING_PROGRAM)
    failures += report(out == ["1", "1", "0"], "compiled and ran: u2' moved by -k_T (q2 - x_T) / M2 "
                       "to rounding, no dissipated power: %s" % (" ".join(out) if out else error))
    # Without its energy, or with an energy its force does not have, the generator stops,
    # naming the load.
    for what, gen in (("left out", conservative_load(potential=False)),
                      ("not its force's", conservative_load(wrong_potential=True))):
        try:
            with contextlib.redirect_stdout(io.StringIO()):
                gen.render()
            refused = ""
        except SystemExit as stop:
            refused = str(stop)
        failures += report("throwaway_spring" in refused,
                           "its energy %s: the generator refuses it (%s)" % (what, refused[:90]))
    return failures


def hostile_rows():
    """A row the table cannot hold stops the generator with one line naming its key (no
    traceback, no C++ that fails to compile later): an unknown role or rule, a section with no
    group, a key or symbol declared twice, a missing or empty doc, a key or member that is no
    C++ name, a default that is not a finite number or breaks its own rule, a range with lo > hi,
    a symbol the derivation uses itself, a reconfigure range without max or with min > max."""
    failures = 0
    good = {"key": "damping.bad", "symbol": "c_X", "unit": "", "rule": "non-negative",
            "default": 0, "role": "dissipative", "doc": "x"}
    cases = [("an unknown role", dict(good, role="dissipativ")),
             ("a section without a group", dict(good, key="dampng.bad")),
             ("a key declared twice", dict(good, key="damping.spring", symbol="c_X")),
             ("a symbol declared twice", dict(good, symbol="c_S")),
             ("an unknown rule", dict(good, rule="postive")),
             ("no doc line", {k: v for k, v in good.items() if k != "doc"}),
             ("an empty doc line", dict(good, doc="  ")),
             ("a key that is no C++ name", dict(good, key="damping.extra-joint")),
             ("a key with a space", dict(good, key="damping.extra joint")),
             ("a key without a section", dict(good, key="bad")),
             ("a NaN default", dict(good, default=float("nan"))),
             ("an infinite default", dict(good, default=float("inf"))),
             ("a default that is text", dict(good, default="abc")),
             ("a default that breaks its rule", dict(good, default=-5)),
             ("a range with lo > hi", dict(good, rule={"range": [5, 1]}, default=2)),
             ("a range of text", dict(good, rule={"range": ["a", "b"]})),
             ("a range of one bound", dict(good, rule={"range": [1]})),
             ("a symbol the derivation uses", dict(good, symbol="u1")),
             ("a symbol that is a C++ keyword", dict(good, symbol="double")),
             ("a reconfigure range without max", dict(good, reconfigure={"min": 0})),
             ("a reconfigure range with min > max", dict(good, reconfigure={"min": 2, "max": 1}))]
    for what, entry in cases:
        gen = generator()
        try:
            gen.ROWS.append(gen.parameter_table.Row(entry, gen.GROUPS))
            gen.parameter_table.check(gen.ROWS)
            refused = ""
        except SystemExit as stop:
            refused = str(stop)
        failures += report(refused.startswith("parameters.yaml: " + entry["key"] + ":") and
                           refused.count("parameters.yaml") == 1,
                           "%s is refused, naming the key (%s)" % (what, refused[:100]))
    # A table file that is not one: one line, no traceback.
    gen = generator()
    with tempfile.TemporaryDirectory() as work:
        for what, text in (("an empty file", ""), ("a YAML syntax error", "groups: [\n"),
                           ("tabs", "groups:\n\tdamping: 1\n"), ("a list", "- 1\n"),
                           ("parameters not a list", "groups: {}\nparameters: 5\n"),
                           ("a row that is a number", "groups: {}\nparameters: [5]\n")):
            path = os.path.join(work, "parameters.yaml")
            with open(path, "w") as f:
                f.write(text)
            try:
                gen.parameter_table.load(path)
                refused = ""
            except SystemExit as stop:
                refused = str(stop)
            failures += report(refused.startswith("parameters.yaml: "),
                               "a table that is %s is refused (%s)" % (what, refused[:90]))
    return failures


def main():
    failures = a_resistance() + a_conservative_load() + hostile_rows()
    print("%d failed" % failures)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
