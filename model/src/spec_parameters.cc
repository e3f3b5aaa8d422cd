#include "gearnvh/model/spec_parameters.h"

#include <regex>
#include <stdexcept>

#include "gearnvh/model/count_text.h"
#include "gearnvh/model/input_error.h"

namespace gearnvh {

const std::vector<std::string>& VariableParameters() {
  static const std::vector<std::string> names{
      "operating.speed",    "operating.torque",          "mesh.backlash",
      "mesh.damping_ratio", "mesh.friction_coefficient", "operating.excitation[0].amplitude"};
  return names;
}

namespace {

// The train parameter a schema-1 name is on the train TrainOf makes of the pair
// (operating.torque: operating.loads[0].torque; mesh.backlash: meshes[0].backlash), nullopt when
// `name` is not one of VariableParameters().
std::optional<std::string> TrainParameterOfPair(const std::string& name) {
  if (name == "operating.speed" || name == "operating.excitation[0].amplitude") return name;
  if (name == "operating.torque") return "operating.loads[0].torque";
  if (name == "mesh.backlash" || name == "mesh.damping_ratio" ||
      name == "mesh.friction_coefficient") {
    return "meshes[0]" + name.substr(4);
  }
  return std::nullopt;
}

}  // namespace

void SetParameter(GearboxSpec& spec, const std::string& name, double value) {
  const std::optional<std::string> train_name = TrainParameterOfPair(name);
  if (!train_name) {
    std::string known;
    for (const std::string& n : VariableParameters()) known += (known.empty() ? "" : ", ") + n;
    throw ParameterNotVariable(name, "must be one of " + known);
  }
  if (name == "operating.excitation[0].amplitude" && spec.operating.excitation.empty()) {
    throw ParameterNotVariable(name, "the gearbox has no operating.excitation order to vary");
  }
  // The pair is the train TrainOf makes of it: one registry, the train's.
  TrainSpec train = TrainOf(spec);
  SetTrainParameter(train, *train_name, value, name);
  spec = GearboxOf(train);
}

namespace {

const char* const kForms =
    "operating.speed, operating.loads[i].torque, operating.loads[i].viscous, "
    "operating.excitation[i].amplitude, "
    "meshes[i].backlash, meshes[i].damping_ratio, meshes[i].friction_coefficient (i the index "
    "in the file's list, from 0), couplings.NAME.stiffness or couplings.NAME.damping";

// A parsed name: its list ("operating.loads", ...), index and key; list empty for operating.speed.
// A coupling is named, not indexed: list "couplings", `entry` its name.
struct TrainParameterName {
  std::string list;
  size_t index = 0;
  std::string key;
  std::string entry{};
};

std::optional<TrainParameterName> Parse(const std::string& name) {
  if (name == "operating.speed") return TrainParameterName{"", 0, "speed"};
  static const std::regex coupling(R"(^couplings\.(.+)\.(stiffness|damping)$)");
  std::smatch c;
  if (std::regex_match(name, c, coupling)) {
    return TrainParameterName{"couplings", 0, "coupling_" + c[2].str(), c[1].str()};
  }
  static const std::regex indexed(
      R"(^(operating\.loads|operating\.excitation|meshes)\[([0-9]{1,6})\]\.([a-z_]+)$)");
  std::smatch m;
  if (!std::regex_match(name, m, indexed)) return std::nullopt;
  TrainParameterName p{m[1].str(), std::stoul(m[2].str()), m[3].str()};
  const bool known = (p.list == "operating.loads" && (p.key == "torque" || p.key == "viscous")) ||
                     (p.list == "operating.excitation" && p.key == "amplitude") ||
                     (p.list == "meshes" && (p.key == "backlash" || p.key == "damping_ratio" ||
                                             p.key == "friction_coefficient"));
  return known ? std::optional<TrainParameterName>(p) : std::nullopt;
}

// The entry `index` of a list of `size`, or InputError naming what the file has.
void RequireIndex(const TrainParameterName& p, size_t size, const std::string& name,
                  const std::string& field, const std::string& entries) {
  if (p.index < size) return;
  throw InputError(field, 0, name,
                   size == 0 ? "the file has no " + p.list + " entry to vary"
                             : "the file's " + p.list + " has " + Count(size, "entry", "entries") +
                                   " (" + entries + ")");
}

}  // namespace

std::optional<TrainParameter> TrainParameterOf(const std::string& name) {
  const std::optional<TrainParameterName> p = Parse(name);
  if (!p) return std::nullopt;
  if (p->key == "speed") return TrainParameter::kSpeed;
  if (p->key == "torque") return TrainParameter::kLoadTorque;
  if (p->key == "viscous") return TrainParameter::kLoadViscous;
  if (p->key == "amplitude") return TrainParameter::kExcitationAmplitude;
  if (p->key == "backlash") return TrainParameter::kBacklash;
  if (p->key == "damping_ratio") return TrainParameter::kDampingRatio;
  if (p->key == "coupling_stiffness") return TrainParameter::kCouplingStiffness;
  if (p->key == "coupling_damping") return TrainParameter::kCouplingDamping;
  return TrainParameter::kFrictionCoefficient;
}

std::string TrainParameterRejection(const std::string& name) {
  if (name == "operating.torque") {
    return "is a schema-1 parameter; a gear train's torques are operating.loads[i].torque. A "
           "gear train varies " +
           std::string(kForms);
  }
  if (name.rfind("mesh.", 0) == 0) {
    return "is a schema-1 parameter; a gear train's meshes are meshes[i]. A gear train varies " +
           std::string(kForms);
  }
  return "is not a parameter a gear train can vary: one of " + std::string(kForms);
}

void SetTrainParameter(TrainSpec& spec, const std::string& name, double value,
                       const std::string& field) {
  const std::optional<TrainParameterName> p = Parse(name);
  const std::optional<TrainParameter> kind = TrainParameterOf(name);
  if (!p || !kind) throw InputError(field, 0, name, TrainParameterRejection(name));
  switch (*kind) {
    case TrainParameter::kSpeed:
      spec.operating.speed = value;
      return;
    case TrainParameter::kLoadTorque: {
      std::string entries;
      for (size_t i = 0; i < spec.operating.loads.size(); ++i) {
        entries += (i ? ", " : "") + std::to_string(i) + ": on " + spec.operating.loads[i].on;
      }
      RequireIndex(*p, spec.operating.loads.size(), name, field, entries);
      TrainLoad& load = spec.operating.loads[p->index];
      if (!load.pinion_torque) {
        load.torque = value;
        return;
      }
      // A schema-1 load written on the pinion varies as written; the output resists its z2 / z1
      // times (GearboxSpec::WheelTorque's expression, so the pair and its train agree bitwise).
      if (!IsSchemaOnePair(spec)) {
        throw std::logic_error("SetTrainParameter: a pinion torque on a train of another form");
      }
      load.pinion_torque = value;
      load.torque = value * static_cast<double>(spec.FindGear("wheel")->gear.teeth) /
                    spec.FindGear("pinion")->gear.teeth;
      return;
    }
    case TrainParameter::kLoadViscous: {
      std::string entries;
      for (size_t i = 0; i < spec.operating.loads.size(); ++i) {
        entries += (i ? ", " : "") + std::to_string(i) + ": on " + spec.operating.loads[i].on;
      }
      RequireIndex(*p, spec.operating.loads.size(), name, field, entries);
      spec.operating.loads[p->index].viscous = value;
      return;
    }
    case TrainParameter::kExcitationAmplitude: {
      std::string entries;
      for (size_t i = 0; i < spec.operating.excitation.size(); ++i) {
        entries += (i ? ", " : "") + std::to_string(i) + ": order " +
                   std::to_string(spec.operating.excitation[i].order);
      }
      RequireIndex(*p, spec.operating.excitation.size(), name, field, entries);
      ExcitationOrder& order = spec.operating.excitation[p->index];
      if (order.kind == ExcitationKind::kTorque) {
        // Axes carry one unit per parameter name (rad/s^2 here): a torque's would be mislabelled.
        throw InputError(field, 0, name,
                         "is the amplitude of a torque order (N m), which is not an axis yet: "
                         "an axis varies an acceleration order's amplitude (rad/s^2)");
      }
      order.amplitude = value;
      return;
    }
    case TrainParameter::kBacklash:
    case TrainParameter::kDampingRatio:
    case TrainParameter::kFrictionCoefficient: {
      std::string entries;
      for (size_t i = 0; i < spec.meshes.size(); ++i) {
        entries += (i ? ", " : "") + std::to_string(i) + ": " + spec.meshes[i].Name();
      }
      RequireIndex(*p, spec.meshes.size(), name, field, entries);
      MeshSpec& mesh = spec.meshes[p->index].mesh;
      (*kind == TrainParameter::kBacklash       ? mesh.backlash
       : *kind == TrainParameter::kDampingRatio ? mesh.damping_ratio
                                                : mesh.friction_coefficient) = value;
      return;
    }
    case TrainParameter::kCouplingStiffness:
    case TrainParameter::kCouplingDamping: {
      std::string names;
      for (TrainCoupling& c : spec.couplings) {
        if (c.name == p->entry) {
          (*kind == TrainParameter::kCouplingStiffness ? c.stiffness : c.damping) = value;
          return;
        }
        names += (names.empty() ? "" : ", ") + c.name;
      }
      throw InputError(field, 0, name,
                       names.empty() ? "the file has no couplings entry to vary"
                                     : "names no coupling of the file (" + names + ")");
    }
  }
}

}  // namespace gearnvh
