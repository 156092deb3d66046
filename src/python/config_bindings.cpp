// kane_sim._core.Config: the one config loader, from Python.
#include <sstream>

#include <pybind11/stl.h>

#include "kane_sim/config/parameter_schema.h"
#include "kane_sim/model/mechanism_model.h"
#include "kane_sim/sim/config_check.h"
#include "python_layer.h"

namespace kane_sim {
namespace python {
const ParameterSpec& specOf(const std::string& name) {
  const size_t dot = name.find('.');
  const ParameterSpec* spec =
      dot == std::string::npos ? nullptr : findParameter(name.substr(0, dot), name.substr(dot + 1));
  if (!spec)
    throw ConfigError(name,
                      "is not a parameter: names are 'section.key' as in the config file "
                      "(kane_sim.Config.names() lists them)");
  return *spec;
}

PythonConfig::PythonConfig(YAML::Node tree, std::string source)
    : tree_(std::move(tree)), loaded_(loadSimulationConfig(tree_)), source_(std::move(source)) {}

PythonConfig PythonConfig::fromFile(const std::string& path) {
  const std::string file = path.empty() ? defaultConfigFile() : path;
  return PythonConfig(loadYamlFile(file), file);
}

PythonConfig PythonConfig::fromYaml(const std::string& text) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw ConfigError("file", "is not valid YAML: " + std::string(e.what()));
  }
  return PythonConfig(root, "<dict>");
}

std::string PythonConfig::yaml() const {
  YAML::Emitter out;
  out << tree_;
  return std::string(out.c_str()) + "\n";
}

py::object PythonConfig::get(const std::string& name) const {
  const ParameterSpec& spec = specOf(name);
  Config& config = const_cast<Config&>(loaded_.config);  // the accessors take Config&; read only
  const ConfigField& f = spec.field;
  if (f.number) return py::float_(f.number(config));
  if (f.whole) return py::int_(f.whole(config));
  if (f.flag) return py::bool_(f.flag(config));
  if (f.text) return py::str(f.text(config));
  return py::str(spec.choices.at(static_cast<size_t>(f.get_choice(config))));
}

PythonConfig PythonConfig::with(const std::string& name, const std::string& value_yaml) const {
  return with({{name, value_yaml}});
}

PythonConfig PythonConfig::with(
    const std::vector<std::pair<std::string, std::string>>& values) const {
  YAML::Node tree = YAML::Clone(tree_);
  for (const auto& [name, value_yaml] : values) {
    const ParameterSpec& spec = specOf(name);
    YAML::Node value;
    try {
      value = YAML::Load(value_yaml);
    } catch (const YAML::Exception& e) {
      throw ConfigError(name, "got a value that is not a YAML scalar: " + std::string(e.what()));
    }
    setConfigValue(tree, spec.section, spec.key, value);
  }
  return PythonConfig(tree, source_);  // validated once, with every value in place
}

std::vector<std::string> PythonConfig::names() {
  std::vector<std::string> out;
  for (const ParameterSpec& spec : parameterSchema()) out.push_back(spec.path());
  return out;
}

bool PythonConfig::reconfigurable(const std::string& name) { return specOf(name).reconfigurable(); }

std::string PythonConfig::role(const std::string& name) { return roleName(specOf(name).role); }

std::string PythonConfig::law(const std::string& name) {
  return lawOfCoefficient(specOf(name).path());
}

void bindConfig(py::module_& m) {
  py::class_<PythonConfig>(m, "Config",
                           "A validated config: the loader's checks, values by config name.")
      .def_static("from_file", &PythonConfig::fromFile, py::arg("path") = "",
                  "Load a config file ('' = the package's config/mechanism.yaml).")
      .def_static("from_yaml", &PythonConfig::fromYaml, py::arg("text"), "Load YAML text.")
      .def("get", &PythonConfig::get, py::arg("name"))
      .def("with_value",
           py::overload_cast<const std::string&, const std::string&>(&PythonConfig::with,
                                                                     py::const_),
           py::arg("name"), py::arg("value_yaml"))
      .def("with_values",
           py::overload_cast<const std::vector<std::pair<std::string, std::string>>&>(
               &PythonConfig::with, py::const_),
           py::arg("values"), "A copy with every (name, YAML scalar) set, validated together.")
      .def_static("names", &PythonConfig::names, "Every parameter's config name.")
      .def_static("reconfigurable", &PythonConfig::reconfigurable, py::arg("name"))
      .def_static("role", &PythonConfig::role, py::arg("name"),
                  "The parameter's role: inertial, geometric, gravity, stiffness, dissipative, "
                  "load shape, drive, contact, initial state, operational or measurement.")
      .def_static("law", &PythonConfig::law, py::arg("name"),
                  "The law of the load the parameter is the coefficient of: viscous, coulomb, "
                  "elastic, or '' for none.")
      .def_property_readonly("warnings", &PythonConfig::warnings)
      .def_property_readonly("source", &PythonConfig::source)
      .def("yaml", &PythonConfig::yaml, "The config as YAML text (a file for `simulate`).");
}

}  // namespace python
}  // namespace kane_sim
