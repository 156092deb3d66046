"""The mechanism's parameter table (codegen/parameters.yaml), read once, and what is written
from it: MechanismParameters (include/kane_sim/model/mechanism_parameters.h) and the config
schema's rows (src/config/mechanism_parameter_rows.cpp). generate_equations.py writes the
equations' constants from the same rows (equation_parameters()).
"""
import math
import os
import re

import yaml

HERE = os.path.dirname(os.path.abspath(__file__))
TABLE = os.path.join(HERE, "parameters.yaml")
ROOT = os.path.normpath(os.path.join(HERE, ".."))
STRUCT_OUTPUT = os.path.join(ROOT, "include", "kane_sim", "model", "mechanism_parameters.h")
ROWS_OUTPUT = os.path.join(ROOT, "src", "config", "mechanism_parameter_rows.cpp")

# ParameterRole's enumerators by the table's names; the roles whose rows are constants of the
# equations (parameter_schema.cpp's inEquations() says the same, checked when the schema is
# built).
ROLES = {"inertial": "kInertial", "geometric": "kGeometric", "gravity": "kGravity",
         "stiffness": "kStiffness", "dissipative": "kDissipative", "load shape": "kLoadShape",
         "drive": "kDrive", "contact": "kContact"}
IN_EQUATIONS = {"inertial", "geometric", "gravity", "stiffness", "dissipative", "load shape"}
RULES = {"finite": "kAny", "positive": "kPositive", "non-negative": "kNonNegative",
         "flag": "kFlag"}


# A C++ identifier in lower snake case (a key's section and name, a member's parts).
IDENTIFIER = re.compile(r"^[a-z][a-z0-9_]*$")
# An equation symbol: a C++ identifier that is not one of the derivation's own names.
SYMBOL = re.compile(r"^[A-Za-z][A-Za-z0-9_]*$")
RESERVED_SYMBOLS = {"q1", "q2", "u1", "u2", "M_m", "c", "v", "x", "x0", "t", "p", "s0", "e",
                    "double", "int", "float", "auto", "const", "return", "Real"}


class TableError(SystemExit):
    """A row the table cannot hold: the generator stops, naming it."""


def refuse(key, text):
    raise TableError("parameters.yaml: %s: %s" % (key, text))


def as_number(value):
    """A finite number as the table writes one (PyYAML reads 1e3, without a point, as text), or
    None."""
    if isinstance(value, bool):
        return None
    if isinstance(value, str) and re.match(r"^[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$", value):
        value = float(value)
    if isinstance(value, (int, float)) and math.isfinite(value):
        return float(value)
    return None


def finite_number(value):
    return as_number(value) is not None


class Row:
    """One parameter, with the names every consumer derives from its key."""

    def __init__(self, entry, groups):
        if not isinstance(entry, dict):
            raise TableError("parameters.yaml: a row is a mapping of key, symbol, unit, ...; "
                             "got %r" % (entry,))
        self.entry = entry
        self.key = str(entry.get("key"))
        parts = self.key.split(".")
        if len(parts) != 2 or not all(IDENTIFIER.match(x) for x in parts):
            refuse(self.key, "a key is <section>.<name>, each lower snake case (letters, digits, _)")
        self.section, self.name = parts
        if "member" in entry:
            self.member = str(entry["member"])
            if not all(IDENTIFIER.match(x) for x in self.member.split(".")):
                refuse(self.key, "member %r is not a C++ member path" % self.member)
        elif self.section == "mechanism":
            self.member = self.name
        elif self.section in groups:
            self.member = self.section + "." + self.name
        else:
            refuse(self.key, "section %s has no group; give its member" % self.section)
        self.constant = self.member.replace(".", "_")  # its field in generated::Constants
        for field in ("role", "rule", "default", "doc"):
            if field not in entry:
                refuse(self.key, "has no %s" % field)
        self.role = entry.get("role")
        if self.role not in ROLES:
            refuse(self.key, "role %r is not one of %s" % (self.role, ", ".join(ROLES)))
        self.symbol = str(entry.get("symbol", ""))
        self.equation_symbol = str(entry.get("equation_symbol", self.symbol))
        if self.in_equations() and (not SYMBOL.match(self.equation_symbol)
                                    or self.equation_symbol in RESERVED_SYMBOLS):
            refuse(self.key, "equation symbol %r is not a C++ identifier free in the derivation "
                   "(not one of %s)" % (self.equation_symbol, ", ".join(sorted(RESERVED_SYMBOLS))))
        self.unit = str(entry.get("unit", ""))
        self.doc = " ".join(str(entry["doc"] or "").split())
        if not self.doc:
            refuse(self.key, "its doc line is empty")
        self.flag = entry["rule"] == "flag"
        self.default = entry["default"]
        self.check_rule_and_default()
        self.check_reconfigure()

    def check_rule_and_default(self):
        rule, default = self.entry["rule"], self.default
        try:
            rule_cpp(rule)
        except ValueError as e:
            refuse(self.key, str(e))
        if self.flag:
            if not isinstance(default, bool):
                refuse(self.key, "a flag's default is true or false, got %r" % (default,))
            return
        if default in ("required", "derived"):
            if default == "derived" and not self.entry.get("default_text"):
                refuse(self.key, "a derived default says how in default_text")
            return
        if not finite_number(default):
            refuse(self.key, "default %r is not a finite number, required or derived" % (default,))
        default = as_number(default)
        if isinstance(rule, dict):
            lo, hi = (as_number(b) for b in rule["range"])
            ok = lo <= default <= hi
        else:
            ok = {"finite": True, "positive": default > 0, "non-negative": default >= 0}[rule]
        if not ok:
            refuse(self.key, "default %r breaks its own rule %r" % (default, rule))

    def check_reconfigure(self):
        r = self.entry.get("reconfigure")
        if r is None:
            return
        if not isinstance(r, dict) or not finite_number(r.get("min")) or \
                not finite_number(r.get("max")) or not as_number(r["min"]) <= as_number(r["max"]):
            refuse(self.key, "reconfigure is {min, max} (finite, min <= max), optionally name; "
                   "got %r" % (r,))
        if "name" in r and not IDENTIFIER.match(str(r["name"])):
            refuse(self.key, "reconfigure name %r is not lower snake case" % (r["name"],))

    def in_equations(self):
        return self.role in IN_EQUATIONS

    def comment(self):
        """'c_O [N m s/rad], pin O: ...' for the C++ fields."""
        unit = " [%s]" % self.unit if self.unit else ""
        return "%s%s %s" % (self.symbol or self.name, unit, self.doc)


def load(path=TABLE):
    """(groups, rows) of the table at `path`."""
    try:
        with open(path) as f:
            table = yaml.safe_load(f)
    except yaml.YAMLError as e:
        raise TableError("parameters.yaml: not YAML: %s" % " ".join(str(e).split()))
    if not isinstance(table, dict) or not isinstance(table.get("groups"), dict) or \
            not isinstance(table.get("parameters"), list):
        raise TableError("parameters.yaml: the table is a mapping with `groups` (a mapping) and "
                         "`parameters` (a list of rows)")
    groups = table["groups"]
    for section, group in groups.items():
        if not IDENTIFIER.match(str(section)) or not isinstance(group, dict) or \
                not re.match(r"^[A-Z][A-Za-z0-9]*$", str(group.get("struct", ""))):
            raise TableError("parameters.yaml: group %r needs a struct name (CamelCase) and a doc"
                             % (section,))
    rows = [Row(entry, groups) for entry in table["parameters"]]
    check(rows)
    return groups, rows


def check(rows):
    """Each key, constant, equation symbol and reconfigure name declared once."""
    seen = set()
    for row in rows:
        names = [row.key, row.constant, row.equation_symbol]
        if "reconfigure" in row.entry:
            names.append("reconfigure " + str(row.entry["reconfigure"].get("name", row.constant)))
        for name in names:
            if name and name in seen:
                refuse(row.key, "%r is declared twice" % name)
            seen.add(name)


def cpp_string(text):
    return '"%s"' % (str(text).replace("\\", "\\\\").replace('"', '\\"')
                     .replace("\n", " ").replace("\r", " "))


def cpp_number(value):
    if value == "inf" or (isinstance(value, float) and math.isinf(value)):
        return "std::numeric_limits<double>::infinity()"
    value = as_number(value)
    text = repr(value)
    return text if ("e" in text or "." in text) else text + ".0"


def default_value(row):
    if row.flag:
        return "true" if row.default else "false"
    if row.default in ("required", "derived"):
        return "kUnset"
    return cpp_number(row.default)


def wrap_comment(text, indent, width=100):
    """`text` as // lines of at most `width` columns."""
    words, lines, line = text.split(), [], ""
    for word in words:
        if line and len(indent) + 3 + len(line) + 1 + len(word) > width:
            lines.append(line)
            line = word
        else:
            line = (line + " " + word).strip()
    lines.append(line)
    return ["%s// %s" % (indent, l) for l in lines]


def wrap_list(head, items, tail, indent, separator=", ", width=100):
    """head + items joined by `separator` + tail, broken before `width` columns; continuation
    lines aligned under the first item."""
    lines, line = [], head
    for i, item in enumerate(items):
        piece = item + (separator.rstrip() if i < len(items) - 1 else tail)
        if line != head and len(line) + 1 + len(piece) > width:
            lines.append(line)
            line = indent + piece
        else:
            line += ("" if line == head else " ") + piece
    lines.append(line)
    return lines


def render_struct(groups, rows):
    """include/kane_sim/model/mechanism_parameters.h."""
    lines = []
    out = lines.append
    out("// GENERATED by codegen/generate_equations.py from codegen/parameters.yaml, the one table")
    out("// of the mechanism's parameters. Do not edit: change the table and regenerate")
    out("// (test/tools/codegen_test.sh fails when they differ). The laws that use them are in")
    out("// model/mechanism_laws.h.")
    out("#ifndef KANE_SIM_MODEL_MECHANISM_PARAMETERS_H")
    out("#define KANE_SIM_MODEL_MECHANISM_PARAMETERS_H")
    out("")
    out("#include <limits>")
    out("#include <tuple>")
    out("")
    out("namespace kane_sim {")
    for section, group in groups.items():
        members = [r for r in rows if r.member.startswith(section + ".")]
        out("")
        lines.extend(wrap_comment(" ".join(group["doc"].split()), ""))
        out("struct %s {" % group["struct"])
        fields = []
        for extra in group.get("extra", []):
            fields.append(extra["name"])
            lines.extend(wrap_comment(extra["doc"], "  "))
            out("  double %s = %s;" % (extra["name"], cpp_number(extra["default"])))
        for row in members:
            field = row.member.split(".", 1)[1]
            fields.append(field)
            lines.extend(wrap_comment(row.comment(), "  "))
            out("  %s %s = %s;" % ("bool" if row.flag else "double", field, default_value(row)))
        out("")
        out("  // Every field, once: equality derives from it.")
        head = "  auto fields() const { return std::tie("
        lines.extend(wrap_list(head, fields, "); }", " " * len(head)))
        dissipative = [r.member.split(".", 1)[1] for r in members if r.role == "dissipative"]
        if dissipative:
            out("  // Any resistance on (its coefficient not 0).")
            out("  bool any() const {")
            lines.extend(wrap_list("    return ", ["%s != 0.0" % f for f in dissipative], ";",
                                   "           ", separator=" ||"))
            out("  }")
        out("};")
    out("")
    out("struct MechanismParameters {")
    out("  static constexpr double kUnset = std::numeric_limits<double>::quiet_NaN();")
    out("")
    top = [r for r in rows if "." not in r.member]
    for row in top:
        lines.extend(wrap_comment(row.comment(), "  "))
        out("  double %s = %s;" % (row.member, default_value(row)))
    for section, group in groups.items():
        out("  %s %s;" % (group["struct"], section))
    out("")
    out("  // Every field, once (equality derives from it: a field left out would let a")
    out("  // reconfiguration of it go unnoticed).")
    out("  auto fields() const {")
    lines.extend(wrap_list("    return std::tie(", [r.member for r in top] + list(groups), ");",
                           " " * len("    return std::tie(")))
    out("  }")
    out("};")
    out("")
    for section, group in groups.items():
        out("inline bool operator==(const %s& a, const %s& b) {" % (group["struct"],
                                                                  group["struct"]))
        lines.extend(wrap_list("  return ", group.get("equality", "a.fields() == b.fields()")
                               .split(), ";", "         ", separator=""))
        out("}")
    out("inline bool operator==(const MechanismParameters& a, const MechanismParameters& b) {")
    out("  return a.fields() == b.fields();")
    out("}")
    out("inline bool operator!=(const MechanismParameters& a, const MechanismParameters& b) {")
    out("  return !(a == b);")
    out("}")
    out("")
    out("}  // namespace kane_sim")
    out("")
    out("#endif  // KANE_SIM_MODEL_MECHANISM_PARAMETERS_H")
    return "\n".join(lines) + "\n"


def rule_cpp(rule):
    """The rule as C++; ValueError for one the table cannot hold."""
    if isinstance(rule, dict):
        bounds = rule.get("range")
        if not isinstance(bounds, list) or len(bounds) != 2 or \
                not all(finite_number(b) for b in bounds) or \
                not as_number(bounds[0]) <= as_number(bounds[1]):
            raise ValueError("a range rule is {range: [lo, hi]} with finite lo <= hi, got %r"
                             % (rule,))
        lo, hi = bounds
        return "{ValueRule::kRange, %s, %s, %s}" % (cpp_number(lo), cpp_number(hi),
                                                   cpp_string(str(rule.get("note", ""))))
    if not isinstance(rule, str) or rule not in RULES:
        raise ValueError("rule %r is not one of %s or {range: [lo, hi]}"
                         % (rule, ", ".join(RULES)))
    return RULES[rule]


def render_rows(groups, rows):
    """src/config/mechanism_parameter_rows.cpp."""
    lines = []
    out = lines.append
    out("// GENERATED by codegen/generate_equations.py from codegen/parameters.yaml, the one table")
    out("// of the mechanism's parameters: their rows of the config schema. Do not edit: change the")
    out("// table and regenerate (test/tools/codegen_test.sh fails when they differ).")
    out("#include \"schema_rows.h\"")
    out("")
    out("namespace kane_sim {")
    out("")
    out("using namespace schema_rows;  // NOLINT: the rows' vocabulary")
    out("")
    out("std::vector<ParameterSpec> mechanismParameterRows() {")
    out("  return {")
    for row in rows:
        entry = row.entry
        field = "mechanism." + row.member
        lines.extend(wrap_list("      row(", [cpp_string(row.section), cpp_string(row.name),
                               "KANE_SIM_FIELD(%s)" % field, cpp_string(row.unit),
                               rule_cpp(entry["rule"])], ")", "          "))
        if row.symbol:
            out("          .symbol(%s)" % cpp_string(row.symbol))
        out("          .role(ParameterRole::%s, %s)" % (
            ROLES[row.role], cpp_string(row.equation_symbol) if row.in_equations() else "\"\""))
        if row.default == "required":
            out("          .required()")
        if "default_text" in entry:
            out("          .defaultText(%s)" % cpp_string(entry["default_text"]))
        if "reconfigure" in entry:
            r = entry["reconfigure"]
            out("          .reconfigure(physical(%s, %s, %s))" % (
                cpp_string(r.get("name", row.constant)), cpp_number(r["min"]),
                cpp_number(r["max"])))
        if "cross_rule" in entry:
            lines.extend(wrap_text(".crossRule(", " ".join(entry["cross_rule"].split()), ")"))
        lines.extend(wrap_text(".doc(", row.doc, "),"))
    out("  };")
    out("}")
    out("")
    out("}  // namespace kane_sim")
    return "\n".join(lines) + "\n"


def wrap_text(head, text, tail, indent="          ", width=100):
    """`head`"text"`tail` as C++ string pieces of at most `width` columns."""
    words, pieces, piece = text.split(" "), [], ""
    room = width - len(indent) - len(head) - len(tail) - 4
    for word in words:
        if piece and len(piece) + 1 + len(word) > room:
            pieces.append(piece + " ")
            piece = word
        else:
            piece = (piece + " " + word) if piece else word
    pieces.append(piece)
    out = [indent + head + cpp_string(pieces[0])]
    out += [indent + "    " + cpp_string(p) for p in pieces[1:]]
    out[-1] += tail
    return out


def equation_parameters(rows):
    """(symbol, constant, comment, source) of every row in the equations, in table order: the
    fields of generated::ConstantsOf and where constantsFrom() reads each."""
    return [(r.equation_symbol, r.constant, r.comment(), "p." + r.member)
            for r in rows if r.in_equations()]
