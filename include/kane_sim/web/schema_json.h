// What the browser's page builds itself from, as one JSON object: the parameter panel's rows
// (the schema's reconfigurable parameters: name, key, symbol, unit, the GUI's bounds, a line of
// doc, the value in force), the CSV columns with their groups (the plots' panels: state, energy,
// power, ledger, ...), the joint names of joint_states and the command modes.
#ifndef KANE_SIM_WEB_SCHEMA_JSON_H
#define KANE_SIM_WEB_SCHEMA_JSON_H

#include <string>

#include "kane_sim/config/config.h"

namespace kane_sim {
namespace web {

// {"parameters": [...], "initial_state": [...], "columns": [...], "joints": [...], "modes":
// [...]}; values from `config`.
std::string schemaJson(const Config& config);

// `text` as a JSON string literal, quotes included.
std::string jsonString(const std::string& text);

}  // namespace web
}  // namespace kane_sim

#endif  // KANE_SIM_WEB_SCHEMA_JSON_H
