// vknerf.TrainConfig: TrainConfig.fast(**fields) / .vanilla(**fields), the fields named as the
// `vknerf train` flags are (--cone-angle is cone_angle) and checked as those flags are, with the
// same messages, all from the one table of fields (vknerf/config_fields.h).
#include <pybind11/stl.h>

#include <algorithm>
#include <limits>

#include "bindings.h"
#include "errors.h"
#include "holders.h"
#include "vknerf/config_fields.h"

namespace py = pybind11;

namespace vknerf::python {

namespace {

// "--cone-angle" -> "cone_angle".
std::string pythonName(const char* flag) {
  std::string s = std::string(flag).substr(2);
  for (char& c : s)
    if (c == '-') c = '_';
  return s;
}

const ConfigField* fieldNamed(const std::string& name) {
  for (const ConfigField& f : configFields())
    if (f.flag.name && pythonName(f.flag.name) == name) return &f;
  return nullptr;
}

std::string fieldNames() {
  std::string s;
  for (const ConfigField& f : configFields())
    if (f.flag.name) s += (s.empty() ? "" : ", ") + pythonName(f.flag.name);
  return s;
}

// The value in the flag's type; the text is what the flag's value would read on a command line.
ConfigValue valueFor(const ConfigField& f, const py::handle& v, std::string& text) {
  const std::string flag = f.flag.name;
  text = py::str(v);
  switch (f.flag.type) {
    case ConfigValueType::Count: {
      if (!py::isinstance<py::int_>(v) || py::isinstance<py::bool_>(v))
        throw InvalidArgument(flag + ": " + text + " is not an integer");
      const long long x = v.cast<long long>();
      if (x < 0 || x > UINT32_MAX) throw InvalidArgument(flag + ": Value " + text + " not in range 0 to 4294967295");
      return uint32_t(x);
    }
    case ConfigValueType::Real:
      if (!(py::isinstance<py::float_>(v) || py::isinstance<py::int_>(v)) || py::isinstance<py::bool_>(v))
        throw InvalidArgument(flag + ": " + text + " is not a number");
      return v.cast<float>();
    case ConfigValueType::Switch:
      if (!py::isinstance<py::bool_>(v)) throw InvalidArgument(flag + ": " + text + " is not True or False");
      return v.cast<bool>();
    case ConfigValueType::Name:
      if (!py::isinstance<py::str>(v)) throw InvalidArgument(flag + ": " + text + " is not a string");
      return v.cast<std::string>();
    case ConfigValueType::Colour: break;
  }
  throw InvalidArgument(flag + ": no flag takes a colour");
}

double asDouble(const ConfigValue& v) {
  if (const auto* u = std::get_if<uint32_t>(&v)) return *u;
  return std::get<float>(v);
}

// The flag's own check, worded as the command line's parser words it
// ("--width: Value 4 not in range 8 to 1024").
void checkAsFlag(const ConfigField& f, const ConfigValue& v, const std::string& text) {
  const std::string flag = f.flag.name;
  const auto range = [&](double lo, double hi, bool integral) {
    const double x = asDouble(v);
    if (x < lo || x > hi || x != x)
      throw InvalidArgument(flag + ": Value " + text + " not in range " +
                            (integral ? std::to_string(uint32_t(lo)) : std::to_string(float(lo))) + " to " +
                            (integral ? std::to_string(uint32_t(hi)) : std::to_string(float(hi))));
  };
  switch (f.flag.check) {
    case ConfigFlag::Check::None: break;
    case ConfigFlag::Check::Range: range(f.flag.lo, f.flag.hi, f.flag.type == ConfigValueType::Count); break;
    case ConfigFlag::Check::Positive:
      if (!(asDouble(v) > 0))
        throw InvalidArgument(flag + ": Value " + text + " not in range " + std::to_string(std::numeric_limits<double>::min()) +
                              " to " + std::to_string(std::numeric_limits<double>::max()));
      break;
    case ConfigFlag::Check::Choice: {
      const std::string& name = std::get<std::string>(v);
      if (std::find(f.choices.begin(), f.choices.end(), name) == f.choices.end()) {
        std::string set;
        for (const std::string& c : f.choices) set += (set.empty() ? "" : ",") + c;
        throw InvalidArgument(flag + ": " + name + " not in {" + set + "}");
      }
      break;
    }
  }
}

// The fields given, set as `vknerf train` sets its flags, then the whole checked by validate().
TrainConfig withFields(TrainConfig cfg, const py::kwargs& fields) {
  for (const auto& [key, value] : fields) {
    const std::string name = py::str(key);
    const ConfigField* f = fieldNamed(name);
    if (!f) throw InvalidArgument("unknown configuration field '" + name + "'; the fields: " + fieldNames());
    if (!f->appliesTo(cfg))
      throw InvalidArgument(name + " (" + f->flag.name + ") applies to the " + (cfg.isFast() ? "vanilla" : "fast") +
                            " model, not TrainConfig." + modelName(cfg.model));
    std::string text;
    const ConfigValue v = valueFor(*f, value, text);
    checkAsFlag(*f, v, text);
    try {
      if (f->flag.apply)
        f->flag.apply(cfg, v);
      else
        f->set(cfg, v);
    } catch (const Error& e) {
      throw InvalidArgument(e.what());
    }
  }
  try {
    cfg.validate();
  } catch (const Error& e) {
    throw InvalidArgument(std::string("the configuration from these fields is invalid: ") + e.what());
  }
  return cfg;
}

py::object asPython(const ConfigValue& v) {
  return std::visit([](const auto& x) -> py::object { return py::cast(x); }, v);
}

std::shared_ptr<Context> contextOr(const py::object& context) {
  if (!context.is_none()) return context.cast<const PyContext&>().ctx;
  return py::module_::import("vknerf").attr("default_context")().cast<const PyContext&>().ctx;
}

}  // namespace

void bindConfig(py::module_& m) {
  py::class_<TrainConfig>(m, "TrainConfig", "A model and its training settings (vanilla: NeRF's; fast: instant-ngp's).")
      .def_static("fast", [](py::object context, const py::kwargs& fields) {
             return withFields(TrainConfig::fast(*contextOr(context)), fields);
           },
           py::arg("context") = py::none(),
           "The fast model sized for the context's device (None: vknerf.default_context()); the fields named "
           "as `vknerf train`'s flags: fast(cone_angle=0.004) is --cone-angle 0.004 (TrainConfig.names() lists them).")
      .def_static("vanilla", [](py::object context, const py::kwargs& fields) {
             return withFields(TrainConfig::vanilla(*contextOr(context)), fields);
           },
           py::arg("context") = py::none())
      .def_static("names", [] {
        py::dict out;
        for (const ConfigField& f : configFields())
          if (f.flag.name) out[py::str(pythonName(f.flag.name))] = f.flag.help;
        return out;
      }, "Every field a keyword sets, with the help of its `vknerf train` flag.")
      .def("replace", [](const TrainConfig& c, const py::kwargs& fields) { return withFields(c, fields); },
           "A copy with these fields set.")
      .def_property_readonly("model", [](const TrainConfig& c) { return std::string(modelName(c.model)); })
      .def("as_dict", [](const TrainConfig& c) {
        py::dict out;
        for (const ConfigField& f : configFields())
          if (f.appliesTo(c)) out[py::str(f.path())] = asPython(f.get(c));
        return out;
      }, "Every field of this model under its checkpoint key.")
      .def("describe", &TrainConfig::describe)
      .def("__repr__", [](const TrainConfig& c) { return "vknerf.TrainConfig(" + c.describe() + ")"; });
}

}  // namespace vknerf::python
