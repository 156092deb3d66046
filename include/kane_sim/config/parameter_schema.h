// The config's parameters, each declared once: its key, the textbook's symbol, unit, rule,
// default (or required), whether it can be reconfigured at run time, and a line of doc. From this
// one list come the loader's reads and checks (config/load_config.h), the dynamic_reconfigure
// description and bindings the node serves, and the parameter table of
// doc/reference/parameters.md (`config_info parameters`, checked against it by a test). Rules
// that tie two parameters together (publish_rate divides physics_rate, rod_inertia's default
// from m and L, the motor line's stall torque) stay in the loader, and `cross_rule` names them
// for the table.
//
// To add a parameter of the mechanism: one row in codegen/parameters.yaml (its struct field, its
// schema row and its constant in the equations are generated from it), and the law that uses it.
// An operational one: a field in config.h's structs (its default is the field's initializer), one
// row in src/config/parameter_schema.cpp, and the code that uses it.
#ifndef KANE_SIM_CONFIG_PARAMETER_SCHEMA_H
#define KANE_SIM_CONFIG_PARAMETER_SCHEMA_H

#include <functional>
#include <string>
#include <vector>

#include "kane_sim/config/config.h"

namespace kane_sim {

// What a value must satisfy (every check is written so that NaN fails it).
struct ValueRule {
  enum Kind {
    kFinite,       // any finite number
    kPositive,     // > 0
    kNonNegative,  // >= 0
    kRange,        // in [lo, hi]
    kZeroOrRange,  // 0 or in [lo, hi]
    kWholeRange,   // a whole number in [lo, hi]
    kFrameName,    // letters, digits, '_' and '/', not starting with '/'
    kAnyName,      // kFrameName, or empty
    kChoice,       // one of `choices`
    kFlag,         // true or false
  };
  Kind kind = kFinite;
  double lo = 0.0;
  double hi = 0.0;
  const char* range_note = "";  // what follows "[lo, hi]" in a message: a unit or a reading
};

// Where a parameter lives in Config. Exactly one member is set, by the value's type.
struct ConfigField {
  double& (*number)(Config&) = nullptr;
  int& (*whole)(Config&) = nullptr;
  bool& (*flag)(Config&) = nullptr;
  std::string& (*text)(Config&) = nullptr;
  // A choice (an enum): its index into ParameterSpec::choices.
  std::function<int(const Config&)> get_choice;
  std::function<void(Config&, int)> set_choice;
};

// A parameter dynamic_reconfigure offers (dynparam, rqt_reconfigure). The GUI bounds only bound
// sliders; values are checked by the loader's rules, unclamped.
struct ReconfigureSpec {
  const char* name = nullptr;  // nullptr: not reconfigurable
  int level = 0;               // 1: changes the physics (energy booked as parameter_energy)
  double gui_min = 0.0;
  double gui_max = 0.0;
};

// What a parameter is to the physics and to the tools: every consumer that treats parameters by
// kind (the equations' constants, equality, identification, the stiffness check's message, the
// tests' random configs) asks the role, never the section or the key's prefix.
enum class ParameterRole {
  kUnset,         // no row may keep it: parameterSchema() refuses one
  kInertial,      // masses and the rod inertia: identifiable from motion
  kGeometric,     // L: measured with a ruler, not identified
  kGravity,       // g: measured, not identified
  kStiffness,     // k: identifiable
  kDissipative,   // a resistance's coefficient (dampers, friction): identifiable, 0 = off
  kLoadShape,     // shapes a load's law without scaling it (friction's v_s): not identified
  kDrive,         // the motor line's no-load speed
  kContact,       // the sliders' contact
  kInitialState,  // where the motion starts
  kOperational,   // how it is simulated, commanded, published, diagnosed
  kMeasurement,   // what the sensors add
};
// Rows of these roles are constants of the equations of motion (each carries its symbol there).
bool inEquations(ParameterRole role);
// Rows of these roles can be estimated from a recorded motion.
bool identifiable(ParameterRole role);
struct ParameterSpec;
// The rows a recorded motion can tell (identify fits them, the observer's alarm suspects them):
// an identifiable role and a number (L and g are measured, a ruler and a level; friction's v_s
// shapes its law).
bool identifiable(const ParameterSpec& spec);
// A role's name as the parameter table prints it ("inertial", "dissipative", ...).
const char* roleName(ParameterRole role);

// One row of the schema (src/config/parameter_schema.cpp writes them as a table, one row each).
struct ParameterSpec {
  const char* section = "";
  const char* key = "";
  const char* symbol = "";  // the textbook's, or ""
  ParameterRole role = ParameterRole::kUnset;
  // Roles inEquations(): the symbol of its constant in the generated equations
  // (generated::kConstantSymbols: "m", "c_O", "F_O", "v_s"), checked when the schema is built.
  const char* equation_symbol = "";
  const char* unit = "";  // SI, or ""
  ValueRule rule;
  ConfigField field;
  bool required = false;
  const char* doc = "";              // one line: what it is
  const char* cross_rule = "";       // a rule involving other parameters (the loader's), or ""
  const char* default_text = "";     // the default when it is not the field's initializer, or ""
  std::vector<std::string> choices;  // kChoice: the valid names, in the enum's order
  const char* choice_noun = "";      // kChoice: "an unknown integrator" (config/choices.h)
  ReconfigureSpec reconfigure;

  std::string path() const { return std::string(section) + "." + key; }
  bool reconfigurable() const { return reconfigure.name != nullptr; }
};

// Every parameter, sections in the config file's order.
const std::vector<ParameterSpec>& parameterSchema();
// The sections, in order; which must be present.
struct SectionSpec {
  const char* name;
  bool required;
};
const std::vector<SectionSpec>& configSections();

// nullptr when absent.
const ParameterSpec* findParameter(const std::string& section, const std::string& key);
const ParameterSpec* findReconfigurable(const std::string& name);

// A parameter's value in `config`, as a number (flags 0/1, choices their index); NaN for text.
double numericValue(const ParameterSpec& spec, const Config& config);
// The value as the config file would spell it ("rk4", "true", "0.5").
std::string valueText(const ParameterSpec& spec, const Config& config);

// The rows of one role, in schema order.
std::vector<const ParameterSpec*> parametersOfRole(ParameterRole role);

// The parameter table of doc/reference/parameters.md (Markdown), one row per parameter.
std::string parameterTable();

// One parameter as the table describes it, one "field: value" line each (config_info
// parameters KEY), and every parameter so, for a terminal (config_info parameters --text).
// parameterText throws std::invalid_argument naming an unknown key.
std::string parameterText(const std::string& key);
std::string parametersText();

}  // namespace kane_sim

#endif  // KANE_SIM_CONFIG_PARAMETER_SCHEMA_H
