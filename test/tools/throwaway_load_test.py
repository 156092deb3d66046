#!/usr/bin/python3
"""A load is one declaration, as far as the code generator goes: a throw-away resistance added to
codegen/generate_equations.py's tables (one PARAMETERS row, its SOURCES entry, one LOADS row),
nothing else, reaches every part of the generated header: the constants struct, constantsFrom(),
LoadName, kLoadInfo (with its coefficient's index), kConstantSymbols, the full rates variant
(and not the undamped one), and variantFor(). The header then compiles and runs with g++: the
new load's coefficient changes u' of the full variant, and variantFor() picks that variant only
when the coefficient is not 0. (The C++ consumers beyond the header read kLoadInfo and the
schema's roles: test_generated_equations' every-parameter test and test_parameter_schema hold
them to the tables.)
Usage: throwaway_load_test.py
"""
import importlib.util
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
GENERATOR = os.path.join(HERE, "..", "..", "codegen", "generate_equations.py")

PROGRAM = r"""
#include <cstdio>
#include "generated_equations.h"
using namespace kane_sim::generated;
int main() {
  Constants c{};
  c.rod_mass = 1; c.rod_half_length = 0.25; c.rod_inertia = 0.02; c.slider3_mass = 0.5;
  c.slider4_mass = 0.8; c.spring_stiffness = 200; c.gravity = 9.81; c.spring_rest_length = 0.3;
  c.friction_velocity_scale = 0.01;
  const RatesVariant off = variantFor(c);
  const Rates before = ratesFor(variantFor(c), c, 0.4, 1.2, 1.5, -0.7, 2.0);
  c.throwaway_damping = 3.0;
  const RatesVariant on = variantFor(c);
  const Rates after = ratesFor(variantFor(c), c, 0.4, 1.2, 1.5, -0.7, 2.0);
  const LoadInfo& load = kLoadInfo[static_cast<int>(LoadName::kThrowawayDamper)];
  std::printf("%d %d %d %s %d %d\n", static_cast<int>(off), static_cast<int>(on),
              after.u2_dot != before.u2_dot && after.dissipated_power > before.dissipated_power,
              load.name, load.coefficient, static_cast<int>(load.site == LoadSite::kSlider4));
  return 0;
}
"""


def main():
    spec = importlib.util.spec_from_file_location("generate_equations", GENERATOR)
    gen = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(gen)
    # The declaration: a second viscous damper on slider 4, coefficient c_T.
    gen.PARAMETERS.append(("c_T", "throwaway_damping", "c_T [N s/m], a throw-away damper"))
    gen.SOURCES["c_T"] = "p.throwaway"
    gen.LOADS.append(("throwaway_damper", "resistance", "slider4", "viscous", "c_T"))
    text = gen.render()
    index = len(gen.PARAMETERS) - 1
    checks = [
        ("the constants struct", "  Real throwaway_damping;"),
        ("constantsFrom()", "c.throwaway_damping = p.throwaway;"),
        ("LoadName", "  kThrowawayDamper,"),
        ("kLoadInfo", '{"throwaway_damper", LoadKind::kResistance, LoadSite::kSlider4, '
                      'LoadLaw::kViscous, %d, "c_T", true}' % index),
        ("kConstantSymbols", '"c_T"};'),
    ]
    failures = 0
    for what, needle in checks:
        ok = needle in text
        failures += not ok
        print("%s %s has the new load" % ("ok  " if ok else "FAIL", what))
    full = text[text.index("inline RatesOf<Real> rates("):]
    undamped = text[text.index("inline RatesOf<Real> ratesUndamped("):
                    text.index("inline RatesOf<Real> ratesViscous(")]
    ok = "const Real c_T = p.throwaway_damping;" in full and "c_T" not in undamped
    failures += not ok
    print("%s the full rates read c_T, the undamped ones do not" % ("ok  " if ok else "FAIL"))
    with tempfile.TemporaryDirectory() as work:
        with open(os.path.join(work, "generated_equations.h"), "w") as f:
            f.write(text)
        with open(os.path.join(work, "main.cpp"), "w") as f:
            f.write(PROGRAM)
        exe = os.path.join(work, "main")
        # The package's headers after `work` (the math functions the header includes), SLEEF
        # for them.
        built = subprocess.run(["g++", "-std=c++17", "-O1", "-Wall", "-Werror", "-I", work,
                                "-I", os.path.join(HERE, "..", "..", "include"),
                                os.path.join(work, "main.cpp"), "-o", exe, "-lsleef"],
                               capture_output=True, text=True)
        if built.returncode != 0:
            print("FAIL the header with the new load does not compile:\n" + built.stderr[:2000])
            failures += 1
        else:
            out = subprocess.run([exe], capture_output=True, text=True).stdout.split()
            want = ["0", "1", "1", "throwaway_damper", str(index), "1"]
            ok = out == want
            failures += not ok
            print("%s compiled and ran: variant off/on, u2' and D' moved, name, index, site: %s"
                  % ("ok  " if ok else "FAIL", " ".join(out)))
    print("%d passed, %d failed" % (len(checks) + 2 - failures, failures))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
