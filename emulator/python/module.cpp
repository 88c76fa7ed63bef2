// The Python module `gpsemu`: the library facade (emulator/library/gpsemu.hpp) with numpy arrays for
// batch generation, and the fault control calls (Receiver.fault/clear/status in-process, Control
// for a running gpsemu's --control socket). Configuration keys are the CLI's (a dict and/or keyword arguments; '_' in a
// keyword stands for '-': start_time= is --start-time).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <map>
#include <string>

#include "emulator/library/gpsemu.hpp"

namespace py = pybind11;
using gpsemu::api::Enu;
using gpsemu::api::Epoch;
using gpsemu::api::Options;

namespace {

bool repeatable(const std::string& key) {
  static const std::map<std::string, bool> table = [] {
    std::map<std::string, bool> t;
    for (const auto& o : gpsemu::api::option_info()) t[o.name] = o.repeatable;
    return t;
  }();
  const auto it = table.find(key);
  return it != table.end() && it->second;
}

/// A Python value as the option's text: str as is, bool "true"/"false", numbers by repr (the
/// shortest text that reads back as the same double), a list/tuple joined by ',' (several values
/// for a repeatable key).
std::string scalar_text(const py::handle& v) {
  if (py::isinstance<py::str>(v)) return v.cast<std::string>();
  if (py::isinstance<py::bool_>(v)) return v.cast<bool>() ? "true" : "false";
  // numpy scalars too: integers through __index__, the rest through float().
  if (py::isinstance<py::int_>(v) || py::hasattr(v, "__index__")) {
    return py::str(py::int_(py::reinterpret_borrow<py::object>(v))).cast<std::string>();
  }
  if (py::isinstance<py::float_>(v) || py::hasattr(v, "__float__")) {
    return py::repr(py::float_(py::reinterpret_borrow<py::object>(v))).cast<std::string>();
  }
  throw py::type_error("gpsemu: option values are str, bool, int, float or a list of them; got " +
                       py::repr(v).cast<std::string>());
}

void add_option(Options& out, std::string key, const py::handle& value) {
  for (char& c : key) {
    if (c == '_') c = '-';
  }
  if (value.is_none()) return;
  std::vector<std::string> values;
  if (py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value)) {
    if (repeatable(key)) {
      for (const auto& item : value) values.push_back(scalar_text(item));
    } else {
      std::string joined;
      for (const auto& item : value) joined += (joined.empty() ? "" : ",") + scalar_text(item);
      values.push_back(joined);
    }
  } else {
    values.push_back(scalar_text(value));
  }
  out.emplace_back(key, values);
}

Options to_options(const py::object& options, const py::kwargs& kwargs) {
  Options out;
  if (!options.is_none()) {
    for (const auto& [k, v] : options.cast<py::dict>()) add_option(out, k.cast<std::string>(), v);
  }
  for (const auto& [k, v] : kwargs) add_option(out, k.cast<std::string>(), v);
  return out;
}

std::optional<std::string> to_file(const py::object& config_file) {
  if (config_file.is_none()) return std::nullopt;
  return py::str(config_file).cast<std::string>();
}

Enu to_enu3(const py::handle& v, const char* what) {
  const auto seq = v.cast<py::sequence>();
  if (seq.size() != 3) throw py::value_error(std::string(what) + ": expected 3 values (east, north, up)");
  return {seq[0].cast<double>(), seq[1].cast<double>(), seq[2].cast<double>()};
}

using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;

Array rows(std::size_t n) { return Array({static_cast<py::ssize_t>(n), py::ssize_t{3}}); }

/// A control request as one JSON line: a str as is, a dict through Python's json.
std::string request_text(const py::object& request) {
  if (py::isinstance<py::str>(request)) return request.cast<std::string>();
  return py::module_::import("json").attr("dumps")(request).cast<std::string>();
}

/// A control answer as a dict.
py::object answer_dict(const std::string& answer) { return py::module_::import("json").attr("loads")(answer); }

/// {"fault": kind, **params} (params' '_'-names as they are: db, ramp_s, east_m, ...).
py::dict fault_request(const std::string& kind, const py::kwargs& params) {
  py::dict d;
  d["fault"] = kind;
  for (const auto& [k, v] : params) d[k] = v;
  return d;
}

py::dict clear_request(const std::string& kind, const py::object& receiver) {
  py::dict d;
  d["clear"] = kind;
  if (!receiver.is_none()) d["receiver"] = receiver;
  return d;
}

/// A running gpsemu's control socket (--control unix:PATH or tcp:HOST:PORT).
struct Control {
  std::string socket;
  double timeout_s = 5.0;
  py::object send(const py::object& request) const {
    return answer_dict(gpsemu::api::control_request(socket, request_text(request), timeout_s));
  }
};

void check_rows(const Array& a, const char* what) {
  if (a.ndim() != 2 || a.shape(1) != 3) throw py::value_error(std::string(what) + ": expected an (n, 3) array");
}

}  // namespace

PYBIND11_MODULE(gpsemu, m) {
  m.doc() = "gpsemu: GPS receiver model (noise, fix, NMEA) configured with the CLI's keys";
  m.attr("__version__") = gpsemu::api::version();
  py::register_exception<gpsemu::api::Error>(m, "Error", PyExc_ValueError);

  py::class_<Epoch>(m, "Epoch", "One epoch of receiver output.")
      .def_readonly("time_ns", &Epoch::time_ns, "epoch time, UTC nanoseconds since 1970")
      .def_readonly("has_fix", &Epoch::has_fix)
      .def_property_readonly("position", [](const Epoch& e) { return py::make_tuple(e.position[0], e.position[1], e.position[2]); },
                             "(lat deg, lon deg, alt m MSL) reported; NaN without fix")
      .def_property_readonly("position_enu", [](const Epoch& e) {
        return py::make_tuple(e.position_enu_m[0], e.position_enu_m[1], e.position_enu_m[2]); },
                             "(east, north, up) metres about the origin; NaN without fix")
      .def_readonly("speed_mps", &Epoch::speed_mps)
      .def_readonly("vel_up_mps", &Epoch::vel_up_mps, "reported vertical velocity, up positive (m/s)")
      .def_readonly("satellites_used", &Epoch::satellites_used)
      .def_readonly("hdop", &Epoch::hdop)
      .def_property_readonly("nmea", [](const Epoch& e) { return py::bytes(e.nmea); },
                             "the epoch's sentences (bytes), as the CLI writes them")
      .def("__repr__", [](const Epoch& e) {
        return "<gpsemu.Epoch time_ns=" + std::to_string(e.time_ns) + (e.has_fix ? " fix>" : " no fix>");
      });

  py::class_<gpsemu::api::NoiseGenerator>(m, "Noise",
      "A noise model alone (keys noise, width, cgrw-*, chrono, gaussian-*, gm-*, composite-*, seed): ENU metres.")
      .def(py::init([](const py::object& options, const py::object& config_file, const py::kwargs& kw) {
             return gpsemu::api::NoiseGenerator(to_options(options, kw), to_file(config_file));
           }),
           py::arg("options") = py::none(), py::kw_only(), py::arg("config_file") = py::none())
      .def("at", [](gpsemu::api::NoiseGenerator& g, double t_s) {
             const Enu e = g.at(std::llround(t_s * 1e9));
             return py::make_tuple(e[0], e[1], e[2]);
           }, py::arg("t_s"), "the error (east, north, up) at t_s seconds after the start; non-decreasing t_s")
      .def("generate", [](gpsemu::api::NoiseGenerator& g, std::size_t n, double rate_hz) {
             Array out = rows(n);
             g.generate(n, rate_hz, out.mutable_data());
             return out;
           }, py::arg("n"), py::arg("rate_hz"),
           "the next n samples at rate_hz as an (n, 3) array of east, north, up metres");

  py::class_<gpsemu::api::Receiver>(m, "Receiver",
      "The receiver model with the CLI's keys (rate, origin, noise, width, seed, start-time, sentences, ...).")
      .def(py::init([](const py::object& options, const py::object& config_file, const py::kwargs& kw) {
             return gpsemu::api::Receiver(to_options(options, kw), to_file(config_file));
           }),
           py::arg("options") = py::none(), py::kw_only(), py::arg("config_file") = py::none())
      .def("step", &gpsemu::api::Receiver::step,
           "the next epoch with the truth of the configured sim: source (the CLI's --fast output)")
      .def("step_enu", [](gpsemu::api::Receiver& r, const py::object& position, const py::object& velocity) {
             return r.step_enu(to_enu3(position, "position"),
                               velocity.is_none() ? Enu{} : to_enu3(velocity, "velocity"));
           }, py::arg("position"), py::arg("velocity") = py::none(),
           "the next epoch with the true position (east, north, up metres) and velocity (m/s)")
      .def("step_geodetic", [](gpsemu::api::Receiver& r, double lat, double lon, double alt, const py::object& velocity) {
             return r.step_geodetic({lat, lon, alt}, velocity.is_none() ? Enu{} : to_enu3(velocity, "velocity"));
           }, py::arg("lat_deg"), py::arg("lon_deg"), py::arg("alt_m"), py::arg("velocity") = py::none(),
           "the next epoch with the true WGS84 position (altitude above MSL) and ENU velocity (m/s)")
      .def("step_no_fix", &gpsemu::api::Receiver::step_no_fix, "the next epoch without truth: no fix")
      .def("run", [](gpsemu::api::Receiver& r, std::size_t n) {
             std::string text;
             for (std::size_t k = 0; k < n; ++k) text += r.step().nmea;
             return py::bytes(text);
           }, py::arg("n"), "the NMEA bytes of the next n step() epochs")
      .def("track", [](gpsemu::api::Receiver& r, const Array& positions, const py::object& velocities) {
             check_rows(positions, "positions");
             const std::size_t n = static_cast<std::size_t>(positions.shape(0));
             Array vel;
             if (!velocities.is_none()) {
               vel = velocities.cast<Array>();
               check_rows(vel, "velocities");
               if (static_cast<std::size_t>(vel.shape(0)) != n) throw py::value_error("velocities: not as many rows as positions");
             }
             Array enu = rows(n), lla = rows(n);
             py::array_t<std::int64_t> times(static_cast<py::ssize_t>(n));
             std::string text;
             const double* p = positions.data();
             const double* v = velocities.is_none() ? nullptr : vel.data();
             double* e = enu.mutable_data();
             double* g = lla.mutable_data();
             std::int64_t* t = times.mutable_data();
             for (std::size_t k = 0; k < n; ++k) {
               const Enu vk = v ? Enu{v[3 * k], v[3 * k + 1], v[3 * k + 2]} : Enu{};
               const Epoch ep = r.step_enu({p[3 * k], p[3 * k + 1], p[3 * k + 2]}, vk);
               for (int i = 0; i < 3; ++i) {
                 e[3 * k + i] = ep.position_enu_m[i];
                 g[3 * k + i] = ep.position[i];
               }
               t[k] = ep.time_ns;
               text += ep.nmea;
             }
             py::dict out;
             out["time_ns"] = times;
             out["enu"] = enu;
             out["lla"] = lla;
             out["nmea"] = py::bytes(text);
             return out;
           }, py::arg("positions"), py::arg("velocities") = py::none(),
           "one epoch per row of an (n, 3) ENU truth array: dict of time_ns (n,), enu (n, 3), "
           "lla (n, 3) (NaN rows without fix) and nmea (bytes)")
      .def("control", [](gpsemu::api::Receiver& r, const py::object& request) {
             return answer_dict(r.control(request_text(request)));
           }, py::arg("request"),
           "one control request (a dict or a JSON str, as on the --control socket) on this receiver's faults: "
           "the answer as a dict; a fault applies from the next step")
      .def("fault", [](gpsemu::api::Receiver& r, const std::string& kind, const py::kwargs& params) {
             return answer_dict(r.control(request_text(fault_request(kind, params))));
           }, py::arg("kind"), "a fault from the next step, e.g. fault('jam', db=25, ramp_s=5, duration=10)")
      .def("clear", [](gpsemu::api::Receiver& r, const std::string& kind, const py::object& receiver) {
             return answer_dict(r.control(request_text(clear_request(kind, receiver))));
           }, py::arg("kind") = "all", py::arg("receiver") = py::none(), "ends the faults of a kind (or all) at the next step")
      .def("status", [](gpsemu::api::Receiver& r) { return answer_dict(r.control(R"({"status":true})")); },
           "the last epoch and the faults on, as a dict")
      .def_property_readonly("next_epoch_ns", &gpsemu::api::Receiver::next_epoch_ns)
      .def_property_readonly("rate_hz", &gpsemu::api::Receiver::rate_hz)
      .def_property_readonly("origin", [](const gpsemu::api::Receiver& r) {
        const auto o = r.origin();
        return py::make_tuple(o[0], o[1], o[2]); }, "(lat deg, lon deg, alt m MSL)")
      .def("to_enu", [](const gpsemu::api::Receiver& r, double lat, double lon, double alt) {
             const auto x = r.to_enu({lat, lon, alt});
             return py::make_tuple(x[0], x[1], x[2]);
           }, py::arg("lat_deg"), py::arg("lon_deg"), py::arg("alt_m"))
      .def("to_geodetic", [](const gpsemu::api::Receiver& r, double e, double n, double u) {
             const auto x = r.to_geodetic({e, n, u});
             return py::make_tuple(x[0], x[1], x[2]);
           }, py::arg("east_m"), py::arg("north_m"), py::arg("up_m"));

  py::class_<Control>(m, "Control",
      "a running gpsemu's control socket (--control unix:PATH or tcp:HOST:PORT): fault, clear, status, send")
      .def(py::init([](const std::string& socket, double timeout_s) { return Control{socket, timeout_s}; }),
           py::arg("socket"), py::arg("timeout_s") = 5.0)
      .def("send", &Control::send, py::arg("request"), "one request (a dict or a JSON str): the answer as a dict")
      .def("fault", [](const Control& c, const std::string& kind, const py::kwargs& params) {
             return c.send(fault_request(kind, params));
           }, py::arg("kind"), "a fault from the next epoch, e.g. fault('jam', db=25, ramp_s=5, receiver=0)")
      .def("clear", [](const Control& c, const std::string& kind, const py::object& receiver) {
             return c.send(clear_request(kind, receiver));
           }, py::arg("kind") = "all", py::arg("receiver") = py::none())
      .def("status", [](const Control& c) { return c.send(py::str(R"({"status":true})")); })
      .def_readonly("socket", &Control::socket);

  m.def("generate", [](std::size_t n, double rate_hz, const py::object& options, const py::kwargs& kw) {
          gpsemu::api::NoiseGenerator g(to_options(options, kw));
          Array out = rows(n);
          g.generate(n, rate_hz, out.mutable_data());
          return out;
        }, py::arg("n"), py::arg("rate_hz"), py::arg("options") = py::none(),
        "n noise samples at rate_hz from a new model: an (n, 3) array of east, north, up metres");
  m.def("option_names", [] {
    std::vector<std::string> names;
    for (const auto& o : gpsemu::api::option_info()) names.push_back(o.name);
    return names;
  }, "the configuration keys (the CLI's long flags)");
}
