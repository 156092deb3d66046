// The WebAssembly module's JavaScript face (embind): translation only, as the ROS layer is for
// ROS. Errors never cross as C++ exceptions: every call answers an object whose `error` is the
// loader's or the argument check's sentence ("" when it went well).
#include <emscripten/bind.h>
#include <emscripten/val.h>

#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "kane_sim/config/load_config.h"
#include "kane_sim/sim/csv_format.h"
#include "kane_sim/sim/torque_profile.h"
#include "kane_sim/web/live_session.h"
#include "kane_sim/web/run_case.h"
#include "kane_sim/web/schema_json.h"

namespace {

using emscripten::val;
using kane_sim::web::LiveSession;

val floatArray(const std::vector<double>& values) {
  // A copy: the module's memory may grow (and move) after this returns.
  val view = val(emscripten::typed_memory_view(values.size(), values.data()));
  return val::global("Float64Array").new_(view);
}

val stringArray(const std::vector<std::string>& texts) {
  val array = val::array();
  for (const std::string& t : texts) array.call<void>("push", t);
  return array;
}

val failure(const std::string& message) {
  val out = val::object();
  out.set("error", message);
  return out;
}

// torque: kind "none" | "constant" | "step" | "sine" | "table"; text: simulate's flag's text
// (step "T,BEFORE,AFTER", sine "AMP,FREQ[,OFFSET]"), the number for constant; table: t, torque
// pairs one after the other.
std::optional<kane_sim::TorqueProfile> torqueProfile(const std::string& kind,
                                                     const std::string& text,
                                                     const std::vector<double>& table) {
  if (kind == "none") return std::nullopt;
  if (kind == "constant") {
    size_t used = 0;
    double value = 0.0;
    try {
      value = std::stod(text, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != text.size() || used == 0 || !std::isfinite(value))
      throw std::invalid_argument("torque must be a finite number, got '" + text + "'");
    return kane_sim::TorqueProfile::constant(value);
  }
  if (kind == "step" || kind == "sine")
    return kane_sim::TorqueProfile::fromFlag("torque-" + kind, text);
  if (kind == "table") {
    if (table.size() % 2 != 0)
      throw std::invalid_argument("torque table: an odd count of numbers (t, torque pairs)");
    std::vector<std::pair<double, double>> points;
    for (size_t i = 0; i < table.size(); i += 2) points.emplace_back(table[i], table[i + 1]);
    return kane_sim::TorqueProfile::table(std::move(points));
  }
  throw std::invalid_argument("torque: unknown kind '" + kind + "'");
}

// A JavaScript array or typed array of numbers (anything else: an empty vector).
std::vector<double> numbers(const val& array) {
  if (array.isUndefined() || array.isNull()) return {};
  return emscripten::convertJSArrayToNumberVector<double>(array);
}

val runCase(std::string yaml, std::string name, double duration, std::string torque_kind,
            std::string torque_text, val torque_table, double output_rate) {
  try {
    const kane_sim::web::CaseTable t = kane_sim::web::runCase(
        yaml, name, duration, torqueProfile(torque_kind, torque_text, numbers(torque_table)),
        output_rate);
    val out = val::object();
    out.set("error", std::string());
    out.set("columns", stringArray(t.columns));
    out.set("values", floatArray(t.values));
    out.set("warnings", stringArray(t.warnings));
    out.set("refused", t.refused);
    return out;
  } catch (const kane_sim::ConfigError& e) {
    return failure(name + ": " + e.what());
  } catch (const std::exception& e) {
    return failure(e.what());
  }
}

// The live session as the page's worker holds it: open() replaces it.
class Session {
 public:
  std::string open(std::string yaml, std::string name) {
    try {
      session_ = std::make_unique<LiveSession>(yaml, name);
      return "";
    } catch (const kane_sim::ConfigError& e) {
      return name + ": " + e.what();
    } catch (const std::exception& e) {
      return e.what();
    }
  }
  val advance(double seconds, double value, int sample_every) {
    if (!session_) return failure("no session: open a config first");
    try {
      val out = val::object();
      out.set("error", std::string());
      out.set("values", floatArray(session_->advance(seconds, value, sample_every)));
      return out;
    } catch (const std::exception& e) {
      return failure(e.what());
    }
  }
  void reset() {
    if (session_) session_->reset();
  }
  std::string setParameter(std::string name, double value) {
    return session_ ? session_->setParameter(name, value) : "no session";
  }
  std::string setInitialState(std::string key, double value) {
    return session_ ? session_->setInitialState(key, value) : "no session";
  }
  std::string setMode(std::string mode) {
    return session_ ? session_->setMode(mode) : "no session";
  }
  val row() const { return session_ ? floatArray(session_->row()) : val::null(); }
  double time() const { return session_ ? session_->time() : 0.0; }
  double physicsRate() const { return session_ ? session_->config().simulation.physics_rate : 0; }
  std::string configYaml() const { return session_ ? session_->configYaml() : ""; }
  std::string schema() const {
    return session_ ? kane_sim::web::schemaJson(session_->config()) : "";
  }
  val events() { return session_ ? stringArray(session_->takeEvents()) : val::array(); }
  // The drawing: [{link, polygon: Float64Array x0,y0,x1,y1..., color: [r,g,b]}], and the link
  // origins {name: [x, y]}; now, or at the joint values of a bag's joint_states.
  val drawing() const {
    return session_ ? drawingAt(session_->outlines(), session_->origins()) : val::null();
  }
  val drawingAtJoints(val joint_positions) const {
    const std::vector<double> positions = numbers(joint_positions);
    if (!session_ || positions.size() != kane_sim::kNumJoints) return val::null();
    kane_sim::JointValues joints;
    for (int i = 0; i < kane_sim::kNumJoints; ++i) joints.position[i] = positions[i];
    return drawingAt(session_->outlinesAt(joints), session_->originsAt(joints));
  }
  val drawingAtQ(double q1, double q2) const {
    if (!session_) return val::null();
    const kane_sim::JointValues joints = session_->jointsAt(q1, q2);
    return drawingAt(session_->outlinesAt(joints), session_->originsAt(joints));
  }

 private:
  static val drawingAt(const std::vector<kane_sim::web::LinkOutline>& outlines,
                       const std::vector<std::pair<std::string, Eigen::Vector2d>>& origins) {
    val links = val::array();
    for (const kane_sim::web::LinkOutline& o : outlines) {
      std::vector<double> xy;
      for (const Eigen::Vector2d& p : o.polygon) {
        xy.push_back(p.x());
        xy.push_back(p.y());
      }
      val link = val::object();
      link.set("link", o.link);
      link.set("polygon", floatArray(xy));
      link.set("color", floatArray({o.r, o.g, o.b}));
      links.call<void>("push", link);
    }
    val at = val::object();
    for (const auto& [name, p] : origins) at.set(name, floatArray({p.x(), p.y()}));
    val out = val::object();
    out.set("links", links);
    out.set("origins", at);
    return out;
  }

  std::unique_ptr<LiveSession> session_;
};

// One CSV text from rows the page holds, every number as simulate writes it.
std::string csvText(val rows) {
  const std::vector<double> values = numbers(rows);
  const size_t width = kane_sim::csvColumns().size();
  std::ostringstream out;
  kane_sim::writeCsvHeader(out);
  for (size_t i = 0; i + width <= values.size(); i += width)
    kane_sim::writeCsvValues(out, values.data() + i, width);
  return out.str();
}

}  // namespace

EMSCRIPTEN_BINDINGS(kane_sim) {
  emscripten::function("runCase", &runCase);
  emscripten::function("csvText", &csvText);
  emscripten::class_<Session>("Session")
      .constructor<>()
      .function("open", &Session::open)
      .function("advance", &Session::advance)
      .function("reset", &Session::reset)
      .function("setParameter", &Session::setParameter)
      .function("setMode", &Session::setMode)
      .function("setInitialState", &Session::setInitialState)
      .function("row", &Session::row)
      .function("time", &Session::time)
      .function("physicsRate", &Session::physicsRate)
      .function("configYaml", &Session::configYaml)
      .function("schema", &Session::schema)
      .function("events", &Session::events)
      .function("drawing", &Session::drawing)
      .function("drawingAtJoints", &Session::drawingAtJoints)
      .function("drawingAtQ", &Session::drawingAtQ);
}
