// The `prostatesim` Python module (pybind11): python/session.h behind a Python `Scene`. Lengths
// cross in millimetres (positions, tips, depths), as in the scripts and the CSVs; arrays are
// numpy copies (the simulation keeps running under them). step() releases the GIL. Errors:
// bad input (a command's key, a view, a state file) raises ValueError naming the key; a
// simulation fault raises prostatesim.SimulationFault (a RuntimeError) with its tick and particle.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <yaml-cpp/yaml.h>

#include <map>
#include <stdexcept>

#include "engine/model/role.h"
#include "engine/realtime/recording.h"
#include "engine/tools/tool_kind.h"
#include "engine/util/error.h"
#include "python/session.h"

namespace py = pybind11;
using ps::python::Session;

namespace {

py::object g_fault;  // prostatesim.SimulationFault

// Python value -> YAML node (the command's keys, checked by the script parser afterwards)
YAML::Node to_yaml(const py::handle& o, const std::string& key) {
  if (py::isinstance<py::bool_>(o)) return YAML::Node(o.cast<bool>());
  if (py::isinstance<py::int_>(o)) return YAML::Node(o.cast<long long>());
  if (py::isinstance<py::float_>(o)) return YAML::Node(o.cast<double>());
  if (py::isinstance<py::str>(o)) return YAML::Node(o.cast<std::string>());
  if (py::isinstance<py::dict>(o)) {
    YAML::Node n(YAML::NodeType::Map);
    for (auto kv : o.cast<py::dict>()) {
      if (!py::isinstance<py::str>(kv.first)) throw ps::InputError("", 0, key, "keys are strings");
      const std::string k = kv.first.cast<std::string>();
      n[k] = to_yaml(kv.second, key.empty() ? k : key + "." + k);
    }
    return n;
  }
  if (py::isinstance<py::list>(o) || py::isinstance<py::tuple>(o) || py::isinstance<py::array>(o)) {
    YAML::Node n(YAML::NodeType::Sequence);
    for (auto v : o) n.push_back(to_yaml(v, key));
    return n;
  }
  // numpy scalars and other numbers
  if (py::hasattr(o, "__float__")) return YAML::Node(o.attr("__float__")().cast<double>());
  throw ps::InputError("", 0, key, std::string("unsupported value of type ") + py::str(o.get_type().attr("__name__")).cast<std::string>());
}

[[noreturn]] void raise_value_error(const ps::InputError& e) {
  std::string msg;
  if (!e.file().empty()) msg = e.file() + (e.line() > 0 ? ":" + std::to_string(e.line()) : "") + ": ";
  if (!e.field().empty()) msg += "'" + e.field() + "': ";
  throw py::value_error(msg + e.message());
}

template <class F>
auto guarded(F&& f) -> decltype(f()) {
  try {
    return f();
  } catch (const ps::InputError& e) {
    raise_value_error(e);
  } catch (const std::invalid_argument& e) {
    throw py::value_error(e.what());
  }
}

py::array_t<double> vec3_array(const std::vector<ps::Vec3>& v) {
  py::array_t<double> a({static_cast<py::ssize_t>(v.size()), py::ssize_t{3}});
  auto m = a.mutable_unchecked<2>();
  for (size_t i = 0; i < v.size(); ++i)
    for (int k = 0; k < 3; ++k) m(static_cast<py::ssize_t>(i), k) = v[i][k] * 1e3;
  return a;
}

py::list mm(const ps::Vec3& v) { return py::cast(std::vector<double>{v.x() * 1e3, v.y() * 1e3, v.z() * 1e3}); }
py::list unit(const ps::Vec3& v) { return py::cast(std::vector<double>{v.x(), v.y(), v.z()}); }

// The read-out's instrument, as its kind's label ("needle", "probe", "filling").
const char* kind_name(const ps::ToolReadout& r) {
  const ps::ToolKind* k = ps::readout_kind(r);
  return k ? k->label : "other";
}

py::dict snapshot_dict(const ps::Snapshot& s) {
  py::dict d;
  d["tick"] = s.tick;
  d["time_s"] = s.time;
  py::list tools;
  for (const ps::ToolReadout& t : s.tools) {
    py::dict r;
    r["name"] = std::string(t.name.data());
    r["kind"] = kind_name(t);
    r["tip_mm"] = mm(t.tip);
    r["axis"] = unit(t.axis);
    r["depth_mm"] = t.depth * 1e3;
    r["force_n"] = t.force;
    r["force_vec_n"] = unit(t.force_vec);
    r["value"] = t.value;
    r["active"] = t.active;
    tools.append(r);
  }
  d["tools"] = tools;
  py::list events;
  for (const ps::SnapshotEvent& e : s.events) {
    py::dict r;
    r["seq"] = e.seq;
    r["time_s"] = e.time;
    r["tool"] = e.tool;
    r["kind"] = static_cast<int>(e.kind);
    r["position_mm"] = mm(e.position);
    r["depth_mm"] = e.depth * 1e3;
    r["force_n"] = e.force;
    r["text"] = std::string(e.text.data());
    events.append(r);
  }
  d["events"] = events;
  // the biopsy guide line (from the probe), when the scene draws one: entry point and direction
  py::object guide = py::none();
  for (const auto& seg : s.draw.segments)
    if (seg.role == ps::DrawRole::Guide) {
      py::dict g;
      g["entry_mm"] = mm(seg.a);
      g["direction"] = unit((seg.b - seg.a).normalized());
      g["end_mm"] = mm(seg.b);
      guide = g;
      break;
    }
  d["guide"] = guide;
  d["faulted"] = s.faulted;
  d["fault"] = std::string(s.fault.data());
  return d;
}

void check_fault(Session& s, bool ok) {
  if (!ok) PyErr_SetString(g_fault.ptr(), s.fault_text().c_str()), throw py::error_already_set();
}

}  // namespace

PYBIND11_MODULE(prostatesim, m) {
  m.doc() = "ProstateSim: the tissue simulation, its instruments and TRUS images from Python (lengths in mm)";
  g_fault = py::reinterpret_borrow<py::object>(PyErr_NewException("prostatesim.SimulationFault", PyExc_RuntimeError, nullptr));
  m.attr("SimulationFault") = g_fault;

  py::class_<Session>(m, "Scene", "A compiled scenario run tick by tick (the runner of `prostatesim replay`)")
      .def(py::init([](const std::string& path) { return guarded([&] { return std::make_unique<Session>(path); }); }),
           py::arg("path"), "Loads and compiles a scenario YAML file (ValueError naming file, line and key on bad input)")
      .def(
          "step",
          [](Session& s, int64_t ticks) {
            if (ticks < 0) throw py::value_error("'ticks': must be >= 0");
            bool ok;
            {
              py::gil_scoped_release nogil;
              std::lock_guard<std::mutex> lk(s.mutex());
              ok = s.step(ticks);
            }
            check_fault(s, ok);
          },
          py::arg("ticks") = 1, "Runs ticks (the GIL released); SimulationFault when the physics faults")
      .def_property_readonly("tick", &Session::tick, "ticks completed")
      .def_property_readonly("time", &Session::time, "simulated time [s]")
      .def_property_readonly("dt", &Session::dt, "tick [s]")
      .def_property_readonly("name", [](const Session& s) { return s.scene().spec.name; })
      .def_property_readonly("particle_count", [](const Session& s) { return s.model().particle_count(); })
      .def(
          "positions", [](Session& s) { std::lock_guard<std::mutex> lk(s.mutex()); return vec3_array(s.state().x); },
          "current positions, N x 3 float64 [mm], scene frame")
      .def("rest_positions", [](const Session& s) { return vec3_array(s.model().rest_pos); }, "rest positions, N x 3 [mm]")
      .def(
          "component_of",
          [](const Session& s) {
            const ps::Model& mo = s.model();
            py::array_t<int32_t> a(mo.particle_count());
            auto v = a.mutable_unchecked<1>();
            for (size_t c = 0; c < mo.components.size(); ++c)
              for (int i = 0; i < mo.components[c].particle_count; ++i) v(mo.components[c].first_particle + i) = static_cast<int32_t>(c);
            return a;
          },
          "component index of each particle (int32, N)")
      .def(
          "component_names",
          [](const Session& s) {
            std::vector<std::string> n;
            for (const auto& c : s.model().components) n.push_back(c.name);
            return n;
          },
          "component names, by index")
      .def(
          "component_roles",
          [](const Session& s) {
            std::vector<std::string> r;
            for (const auto& c : s.model().components) r.push_back(ps::role_word(c.role));
            return r;
          },
          "component roles ('prostate', 'bladder', 'lesion', ..., 'other'), by index: the scenario's "
          "`role:`, else the default of the name")
      .def(
          "tag_roles",
          [](const Session& s) {
            std::map<std::string, std::string> r;
            const ps::Model& mo = s.model();
            for (size_t t = 0; t < mo.tag_names.size(); ++t) r[mo.tag_names[t]] = ps::role_word(mo.tag_role(static_cast<int>(t)));
            return r;
          },
          "role of each particle tag, by tag name ('lesion' for lesions, 'other' for zones)")
      .def(
          "tagged",
          [](const Session& s, const std::string& tag) {
            const ps::Model& mo = s.model();
            const int t = mo.find_tag(tag);
            if (t < 0) throw py::value_error("'tag': the scene has no particle tag '" + tag + "'");
            std::vector<int32_t> idx;
            for (size_t i = 0; i < mo.particle_tags.size(); ++i)
              if (mo.particle_tags[i] >> t & 1u) idx.push_back(static_cast<int32_t>(i));
            return py::array_t<int32_t>(static_cast<py::ssize_t>(idx.size()), idx.data());
          },
          py::arg("tag"), "indices of the particles carrying a tag (e.g. 'lesion', 'peripheral')")
      .def(
          "command",
          [](Session& s, const py::dict& entry) {
            guarded([&] {
              YAML::Emitter out;
              out << YAML::Flow << to_yaml(entry, "command");
              std::lock_guard<std::mutex> lk(s.mutex());
              s.command(out.c_str());
            });
          },
          py::arg("entry"),
          "Applies a live command before the next tick: the keys of a script timeline entry without `t` "
          "(docs/realtime.md), e.g. {'probe': {'tilt_deg': 5}, 'over_s': 0.2}. ValueError naming the key when it "
          "is malformed, names an instrument the scene lacks, or the tool refuses it")
      .def(
          "probe_pose",
          [](const Session& s) {
            const ps::ProbePose& p = s.probe_pose();
            py::dict d;
            d["insertion_mm"] = p.insertion * 1e3;
            d["offset_mm"] = mm(p.offset);
            d["roll_deg"] = p.roll * 180.0 / 3.14159265358979323846;
            d["tilt_deg"] = p.tilt * 180.0 / 3.14159265358979323846;
            d["yaw_deg"] = p.yaw * 180.0 / 3.14159265358979323846;
            return d;
          },
          "the probe pose commanded so far (the keys of a probe entry)")
      .def(
          "snapshot", [](Session& s) { std::lock_guard<std::mutex> lk(s.mutex()); return snapshot_dict(s.snapshot()); },
          "tick, time_s, tools (name, kind, tip_mm, axis, depth_mm, force_n, ...), events since the last call, guide line")
      .def(
          "ultrasound",
          [](Session& s, const std::string& view) {
            return guarded([&] {
              std::lock_guard<std::mutex> lk(s.mutex());
              const ps::us::UsImage& im = s.ultrasound(view);
              py::array_t<uint8_t> a({im.height, im.width});
              std::copy(im.pixels.begin(), im.pixels.end(), a.mutable_data());
              return a;
            });
          },
          py::arg("view") = "transverse", "one TRUS plane now: 'transverse' or 'sagittal', 2-D uint8 (rows top-down)")
      .def(
          "metrics",
          [](Session& s) {
            return guarded([&] {
              std::lock_guard<std::mutex> lk(s.mutex());
              return py::module_::import("json").attr("loads")(s.metrics_json());
            });
          },
          "the needle session's metrics and score so far (metrics.json of `run --report`, docs/metrics.md)")
      .def(
          "save_state",
          [](Session& s, const std::string& path) {
            guarded([&] {
              std::lock_guard<std::mutex> lk(s.mutex());
              s.save_state(path);
            });
          },
          py::arg("path"), "writes the current state (atomically; `run --state` reads it)")
      .def(
          "load_state",
          [](Session& s, const std::string& path) {
            guarded([&] {
              std::lock_guard<std::mutex> lk(s.mutex());
              s.load_state(path);
            });
          },
          py::arg("path"), "goes on from a state saved from this scenario file (ValueError otherwise)")
      .def(
          "state_hash",
          [](Session& s) {
            std::lock_guard<std::mutex> lk(s.mutex());
            return ps::hex16(s.state_hash());
          },
          "full state hash, 16 hex digits (what `prostatesim replay ... --hash` prints for the same inputs)");
}
