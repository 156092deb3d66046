// The config schema's row vocabulary (private to src/config): how a row of
// src/config/parameter_schema.cpp (the operational sections, by hand) and of
// src/config/mechanism_parameter_rows.cpp (the mechanism's, generated from
// codegen/parameters.yaml) is written. A row names where its value lives in Config
// (KANE_SIM_FIELD: a captureless lambda, nested members having no member pointer), its unit and
// rule; the rest follows as modifiers, only where a row has them.
#ifndef KANE_SIM_CONFIG_SCHEMA_ROWS_H
#define KANE_SIM_CONFIG_SCHEMA_ROWS_H

#include <vector>

#include "kane_sim/config/choices.h"
#include "kane_sim/config/parameter_schema.h"

namespace kane_sim {
namespace schema_rows {

#define KANE_SIM_FIELD(member) \
  +[](Config & c) -> auto& {   \
    return c.member;           \
  }

struct Row {
  ParameterSpec spec;
  Row& symbol(const char* s) {
    spec.symbol = s;
    return *this;
  }
  // What the parameter is (ParameterRole); physical roles name their constant in the equations,
  // by default the row's symbol (written once: .symbol("c_O").role(kDissipative)).
  Row& role(ParameterRole r, const char* equation_symbol = nullptr) {
    spec.role = r;
    spec.equation_symbol = equation_symbol ? equation_symbol : inEquations(r) ? spec.symbol : "";
    return *this;
  }
  Row& required() {
    spec.required = true;
    return *this;
  }
  Row& doc(const char* d) {
    spec.doc = d;
    return *this;
  }
  Row& crossRule(const char* r) {
    spec.cross_rule = r;
    return *this;
  }
  Row& defaultText(const char* t) {
    spec.default_text = t;
    return *this;
  }
  Row& reconfigure(ReconfigureSpec r) {
    spec.reconfigure = r;
    return *this;
  }
  operator ParameterSpec() const { return spec; }  // NOLINT: a row is a spec
};

inline ConfigField fieldOf(double& (*field)(Config&)) {
  ConfigField f;
  f.number = field;
  return f;
}
inline ConfigField fieldOf(int& (*field)(Config&)) {
  ConfigField f;
  f.whole = field;
  return f;
}
inline ConfigField fieldOf(bool& (*field)(Config&)) {
  ConfigField f;
  f.flag = field;
  return f;
}
inline ConfigField fieldOf(std::string& (*field)(Config&)) {
  ConfigField f;
  f.text = field;
  return f;
}

// A number, whole number, flag or text.
template <class Field>
inline Row row(const char* section, const char* key, Field field, const char* unit,
               ValueRule rule) {
  Row r;
  r.spec.section = section;
  r.spec.key = key;
  r.spec.unit = unit;
  r.spec.rule = rule;
  r.spec.field = fieldOf(field);
  return r;
}

// One of an enum's names (config/choices.h holds them, once).
template <class E>
inline Row choice(const char* section, const char* key, E& (*field)(Config&)) {
  Row r;
  r.spec.section = section;
  r.spec.key = key;
  r.spec.rule = ValueRule{ValueRule::kChoice};
  r.spec.field.get_choice = [field](const Config& c) {
    return static_cast<int>(field(const_cast<Config&>(c)));  // only read
  };
  r.spec.field.set_choice = [field](Config& c, int i) { field(c) = static_cast<E>(i); };
  r.spec.choices.assign(Choice<E>::names.begin(), Choice<E>::names.end());
  r.spec.choice_noun = Choice<E>::noun;
  return r;
}

constexpr ValueRule kAny{ValueRule::kFinite};
constexpr ValueRule kPositive{ValueRule::kPositive};
constexpr ValueRule kNonNegative{ValueRule::kNonNegative};
constexpr ValueRule kFlag{ValueRule::kFlag};

// Physical parameters are reconfigured at level 1 (their energy change is booked), the others 0.
constexpr ReconfigureSpec physical(const char* name, double gui_min, double gui_max) {
  return {name, 1, gui_min, gui_max};
}
constexpr ReconfigureSpec operational(const char* name, double gui_min, double gui_max) {
  return {name, 0, gui_min, gui_max};
}

}  // namespace schema_rows

// The mechanism's rows, in codegen/parameters.yaml's order (mechanism_parameter_rows.cpp).
std::vector<ParameterSpec> mechanismParameterRows();

}  // namespace kane_sim

#endif  // KANE_SIM_CONFIG_SCHEMA_ROWS_H
