#include "kane_sim/web/schema_json.h"

#include <cmath>
#include <cstdio>

#include "kane_sim/config/choices.h"
#include "kane_sim/config/parameter_schema.h"
#include "kane_sim/format_number.h"
#include "kane_sim/model/joint_names.h"
#include "kane_sim/sim/csv_format.h"

namespace kane_sim {
namespace web {
namespace {

// JSON has no inf or NaN: null stands for them.
std::string jsonNumber(double value) { return std::isfinite(value) ? formatNumber(value) : "null"; }

}  // namespace

std::string jsonString(const std::string& text) {
  std::string out = "\"";
  for (const char c : text) {
    switch (c) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\t':
        out += "\\t";
        break;
      case '\r':
        out += "\\r";
        break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char escaped[8];
          std::snprintf(escaped, sizeof escaped, "\\u%04x", c);
          out += escaped;
        } else {
          out += c;
        }
    }
  }
  return out + "\"";
}

std::string schemaJson(const Config& config) {
  std::string json = "{\"parameters\":[";
  bool first = true;
  for (const ParameterSpec& p : parameterSchema()) {
    if (!p.reconfigurable()) continue;
    json += std::string(first ? "" : ",") + "{\"name\":" + jsonString(p.reconfigure.name) +
            ",\"key\":" + jsonString(p.path()) + ",\"symbol\":" + jsonString(p.symbol) +
            ",\"unit\":" + jsonString(p.unit) + ",\"doc\":" + jsonString(p.doc) +
            ",\"min\":" + jsonNumber(p.reconfigure.gui_min) +
            ",\"max\":" + jsonNumber(p.reconfigure.gui_max) +
            ",\"value\":" + jsonNumber(numericValue(p, config)) + "}";
    first = false;
  }
  // The initial state: the page's panel edits it (the motion restarts there).
  json += "],\"initial_state\":[";
  first = true;
  for (const ParameterSpec* p : parametersOfRole(ParameterRole::kInitialState)) {
    json += std::string(first ? "" : ",") + "{\"name\":" + jsonString(p->key) +
            ",\"key\":" + jsonString(p->path()) + ",\"symbol\":" + jsonString(p->symbol) +
            ",\"unit\":" + jsonString(p->unit) + ",\"doc\":" + jsonString(p->doc) +
            ",\"value\":" + jsonNumber(numericValue(*p, config)) + "}";
    first = false;
  }
  json += "],\"columns\":[";
  first = true;
  for (const CsvColumn& c : csvColumns()) {
    json += std::string(first ? "" : ",") + "{\"name\":" + jsonString(c.name) +
            ",\"group\":" + jsonString(c.group) + ",\"key\":" + jsonString(c.key) +
            ",\"message_field\":" + jsonString(c.message_field) +
            ",\"message_index\":" + std::to_string(c.message_index) + "}";
    first = false;
  }
  json += "],\"joints\":[";
  for (size_t i = 0; i < kJointNames.size(); ++i)
    json += std::string(i ? "," : "") + jsonString(kJointNames[i]);
  json += "],\"modes\":[";
  for (CommandMode m : {CommandMode::kEffort, CommandMode::kVelocity, CommandMode::kPosition})
    json += std::string(m == CommandMode::kEffort ? "" : ",") + jsonString(commandModeName(m));
  json += "],\"mode\":" + jsonString(commandModeName(config.command.mode)) + "}";
  return json;
}

}  // namespace web
}  // namespace kane_sim
