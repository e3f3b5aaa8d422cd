// TrainSpec: the validated, SI-unit description of a gear train (schema gearnvh/2): any number of
// shafts, gears and meshes. A schema-1 gearbox is the train of two shafts "input" (pinion) and
// "output" (wheel) with one mesh (TrainOf).
//
// Conventions (as schema 1, per mesh): every body's nominal rotation follows from the input speed
// through the meshes (ratio -z_a/z_b); a mesh's first gear drives in the drive-flank sign
// convention; loads are mean torques resisting the rotation of a shaft or of a loose gear.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "gearnvh/model/gearbox_spec.h"

namespace gearnvh {

enum class Mounting {
  kFixed,  // turns with its shaft
  kLoose,  // turns freely on its shaft (its own torsional body, e.g. an idling gear)
};

struct TrainShaft {
  std::string name;
  // Rigid: its own polar inertia, kg m^2 (> 0). Elastic: `elastic` holds the FE description.
  std::optional<double> inertia;
  std::optional<ShaftSpec> elastic;
  std::vector<BearingSpec> bearings;  // rigid shafts; an elastic shaft keeps its own
  // Grounded: it does not turn (the output at standstill in neutral). Its fixed gears mesh with
  // nothing; loose gears on it turn freely on the stationary shaft.
  bool fixed = false;

  bool operator==(const TrainShaft&) const = default;
};

struct TrainGear {
  std::string name;
  std::string shaft;         // a TrainShaft name
  std::optional<double> at;  // m, axial position; required on an elastic shaft
  Mounting mounting = Mounting::kFixed;
  GearSpec gear;

  bool operator==(const TrainGear&) const = default;
};

// Whose polar inertias give a mesh's effective mass m_e = J_a J_b / (J_a r_b^2 + J_b r_a^2), and
// with it the mesh damping c = 2 zeta sqrt(k_mean m_e) and the impact energy 1/2 m_e v^2
// (docs/design.md §11). The two differ only where a shaft carries inertia beyond its gears.
enum class MeshEffectiveMass {
  kBodies,  // the two bodies' (a shaft with every gear and inertia on it): schema 2's default
  kGears,   // the two gears' own: schema 1's contract (TrainOf)
};

struct TrainMesh {
  std::string gear_a, gear_b;  // gear_a drives in the drive-flank sign convention
  MeshSpec mesh;
  // Layout (lateral DOF only): direction of the line of centres from gear a's axis to gear b's,
  // rad about +z from +x. Default 0: every mesh along +x (an unfolded planar layout).
  double center_line_angle = 0.0;
  MeshEffectiveMass effective_mass = MeshEffectiveMass::kBodies;
  std::string Name() const { return gear_a + "-" + gear_b; }

  bool operator==(const TrainMesh&) const = default;
};

struct TrainLoad {
  std::string on;                       // a shaft name or a loose gear's name
  double torque = 0.0;                  // N m, >= 0: mean torque resisting its rotation
  DisplayUnit torque_unit{"N m", 1.0};  // the unit the input wrote it in, for output
  // Schema 1's `operating.torque_on: pinion`: the file gave the torque the pinion transmits, N m,
  // and `torque` (on the output) is that times z_wheel / z_pinion. Kept so that the pair is shown
  // and varied as written.
  std::optional<double> pinion_torque = std::nullopt;
  // Viscous drag c, N m s/rad, >= 0: a torque c |dw| resisting the speed dw of the body relative
  // to `relative_to` (its mean c |dW| adds to `torque`, its fluctuation damps).
  double viscous = 0.0;
  DisplayUnit viscous_unit{"N m s/rad", 1.0};
  // A shaft the drag acts relative to (a loose gear's carrier: needle-bearing drag), its reaction
  // on that shaft; empty: the absolute speed (churning, windage), reaction on the housing.
  std::string relative_to{};

  bool operator==(const TrainLoad&) const = default;
};

// A stage after the first of a multi-stage coupling: where the twist's magnitude passes `from`,
// the coupling's stiffness becomes `stiffness` (symmetric in the twist's sign).
struct TrainCouplingStage {
  double from = 0.0;       // rad, > 0: the previous stage's end (`to` as written)
  double stiffness = 0.0;  // N m/rad, above the previous stage's

  bool operator==(const TrainCouplingStage&) const = default;
};

// A coupling's springs: the first stage's stiffness k_1 (N m/rad) and the stages after it.
struct CouplingSprings {
  double stiffness = 0.0;
  const std::vector<TrainCouplingStage>& stages;
  // The torque at `twist` (N m): k_1 th + sum_s (k_s - k_s-1) sign(th) max(|th| - from_s, 0),
  // continuous and odd in the twist.
  double Torque(double twist) const;
  // The twist (rad) at which the springs carry `torque`: Torque's inverse (it rises in every
  // stage).
  double StaticTwist(double torque) const;
  // The stiffness at `twist` (N m/rad): the stage it lies in (at a stage's start, the one before).
  double TangentStiffness(double twist) const;
};

// A torsional coupling between two turning shafts (a clutch damper, a halfshaft, the spring set of
// a dual-mass flywheel): a spring-damper on their relative angle (the twist th_a - th_b), linear or
// piecewise linear in stages that stiffen with the twist's magnitude (docs/gear-trains.md). The
// shafts turn at one nominal speed (speeds propagate through it as through a 1:1 ratio) and the
// mean torque it carries twists it along its stages (StaticTwist).
struct TrainCoupling {
  std::string name;
  std::string shaft_a, shaft_b;  // `between`, in the order written
  double stiffness = 0.0;        // N m/rad, > 0: the whole coupling's, or its first stage's
  // The stages after the first, `from` ascending; empty: a linear coupling (`stiffness`).
  std::vector<TrainCouplingStage> stages;
  double damping = 0.0;                        // N m s/rad, >= 0
  DisplayUnit stiffness_unit{"N m/rad", 1.0};  // as written, for output
  DisplayUnit damping_unit{"N m s/rad", 1.0};

  DisplayUnit angle_unit{"rad", 1.0};  // the stages' angles as written
  CouplingSprings springs() const { return {stiffness, stages}; }

  bool operator==(const TrainCoupling&) const = default;
};

struct TrainOperating {
  std::string input_shaft;               // the shaft whose mean speed is given
  double speed = 0.0;                    // rad/s, > 0
  DisplayUnit speed_unit{"rad/s", 1.0};  // the unit the input wrote it in, for output
  std::vector<TrainLoad> loads;
  std::vector<ExcitationOrder> excitation;  // each an order of its own shaft's speed (`on`)

  bool operator==(const TrainOperating&) const = default;
};

struct TrainSpec {
  std::string name;
  std::map<std::string, Material> materials;
  std::vector<TrainShaft> shafts;
  std::vector<TrainGear> gears;
  std::vector<TrainMesh> meshes;
  std::vector<TrainCoupling> couplings;  // file order
  TrainOperating operating;
  AnalysisSpec analysis;

  const TrainGear* FindGear(const std::string& name) const;
  const TrainShaft* FindShaft(const std::string& name) const;
  int GearIndex(const std::string& name) const;   // -1 when there is no such gear
  int ShaftIndex(const std::string& name) const;  // -1 when there is no such shaft

  bool operator==(const TrainSpec&) const = default;
};

// The rotating bodies of a train: each shaft with the gears fixed on it, and each loose gear.
enum class BodyKind { kShaft, kLooseGear };

struct TrainBody {
  std::string name;  // the shaft's or the loose gear's name
  BodyKind kind = BodyKind::kShaft;
  int shaft = -1;          // index in TrainSpec::shafts (a loose gear: the shaft it turns on)
  std::vector<int> gears;  // indices in TrainSpec::gears turning with this body
  // Nominal speed, rad/s, signed: > 0 turns the way the input shaft does. From the input speed
  // through the meshes, omega_b = -omega_a z_a / z_b, and the couplings (equal speeds); 0 for a
  // fixed shaft.
  double speed = 0.0;
  // The same per unit input speed, from the tooth ratios alone: what depends on speed ratios only
  // (the static torque flow) is then the same bits at every input speed.
  double speed_ratio = 0.0;
};

struct TrainTopology {
  std::vector<TrainBody> bodies;  // shafts in file order, then loose gears in file order
  std::vector<int> gear_body;     // body of each gear
  int input_body = 0;
  // The spanning tree the speeds were propagated on (meshes first, couplings only to shafts the
  // meshes do not reach): for each body the mesh or the coupling it was reached through (-1 for
  // neither: the input, a fixed shaft, which stands, and in parent_mesh a body reached through a
  // coupling), and the meshes that close a kinematic loop (a coupling never does: refused).
  std::vector<int> parent_mesh;
  std::vector<int> parent_coupling;
  std::vector<int> loop_meshes;
  // The body a body's tree edge leads to, towards the input (-1 at the input and a fixed shaft).
  int ParentBody(const TrainSpec& spec, int body) const;
};

// Bodies, nominal speeds and the spanning tree. Throws InputError for a topology rule (a loose
// gear or shaft that no chain of meshes and couplings connects to the input, a loop whose ratios
// disagree, a coupling that closes a loop or joins a fixed shaft, a fixed shaft that is the input
// or whose fixed gear meshes).
TrainTopology AnalyseTrainTopology(const TrainSpec& spec);

// Static torque flow: every load resists its body's rotation; the input shaft is driven by the
// torque that balances them all (power balance, T_in |w_in| = sum T_j |w_j|). A load's power
// passes through every mesh and coupling on the spanning-tree path from its body to the input; a
// mesh carrying power P transmits T = P / |w_b| on gear b, a coupling T = P / |w|. A mesh that
// closes a loop is not on the tree and carries nothing (the split is statically indeterminate; a
// coupling never closes one: AnalyseTrainTopology refuses it).
struct TrainTorqueFlow {
  double input_torque = 0.0;               // N m driving the input shaft
  std::vector<double> transmitted_torque;  // per mesh, N m on gear b (>= 0)
  // Per coupling, N m, signed: > 0 when shaft_a drives shaft_b (its twist th_a - th_b in their
  // direction of rotation is T / k).
  std::vector<double> coupling_torque;
  std::vector<bool> back_flank_loaded;     // per mesh: power flows from gear b to gear a
  std::vector<int> main_load;  // per mesh, the index of the load sending it most power, or -1
};
TrainTorqueFlow StaticTorqueFlow(const TrainSpec& spec, const TrainTopology& topology);

// What load i does at the spec's nominal speeds. Its body b and the body c it acts relative to
// (none when absolute, or relative to a fixed shaft, which is the housing) turn at W_b, W_c
// (signed); dW = W_b - W_c. The drag T + c |dW| resists dW: on b it is -sgn(dW) (T + c |dW|), on c
// the opposite. Per body, `resisting` is that torque's part against the body's own direction of
// rotation (the tier-1 angles' sense). Its fluctuation is the damping c w w^T on those angles,
// w_b = s_b, w_c = -s_c (s = +1 where W > 0, else -1; no term is on a fixed shaft).
struct LoadAction {
  struct Term {
    int body = 0;
    double resisting = 0.0;  // N m
    double direction = 0.0;  // w's entry
  };
  std::vector<Term> terms;      // the body, then the body it is relative to
  double viscous = 0.0;         // c, N m s/rad
  double relative_speed = 0.0;  // dW, rad/s
  // Whether the drag damps the train's free rotation (c > 0 and dW != 0): its speed then decays
  // and only its angle stays neutral.
  bool DampsFreeRotation() const { return viscous > 0.0 && relative_speed != 0.0; }
};
LoadAction ActionOfLoad(const TrainSpec& spec, const TrainTopology& topology, size_t load);
// Whether any load's drag damps the free rotation (and makes the torque flow speed dependent).
bool DragDampsFreeRotation(const TrainSpec& spec, const TrainTopology& topology);

// Mesh `m` as the schema-1 gearbox of its two gears (pinion = gear_a, wheel = gear_b, their
// elastic shafts with gear_at = the gear's position), at the nominal speed of gear_a and carrying
// `transmitted_torque` on gear_b: the input of the mesh-level model.
GearboxSpec MeshGearbox(const TrainSpec& spec, const TrainTopology& topology, int m,
                        double transmitted_torque);

// The two-shaft, one-mesh train a schema-1 gearbox means: shafts "input" and "output" (rigid ones
// with no inertia of their own), gears "pinion" and "wheel", one mesh, one load on the output.
TrainSpec TrainOf(const GearboxSpec& spec);

// Whether `spec` is a train TrainOf can give (so GearboxOf can take it back), its load agreeing
// with its pinion torque when it has one.
bool IsSchemaOnePair(const TrainSpec& spec);

// The schema-1 gearbox a train of TrainOf's form means: GearboxOf(TrainOf(p)) == p. Throws
// std::invalid_argument when !IsSchemaOnePair(spec).
GearboxSpec GearboxOf(const TrainSpec& spec);

// Range and topology rules (every message names the schema path): names resolve, a mesh joins
// gears on different shafts, every loose gear meshes, helical pairs have equal helix angles and
// opposite hands, every shaft turns (is reached from the input through meshes, fixed gears and
// couplings), and every kinematic loop closes with consistent ratios; no pair of gears meshes
// twice; a coupling joins two distinct rigid, turning shafts with k in (0, kMaxCouplingStiffness]
// and c in [0, kMaxCouplingDamping], at most one per pair and none closing a loop; an excitation
// order acts on a turning shaft. Every mesh obeys the schema-1 gear and mesh rules; the operating
// limits are the train's: the input speed > 0, each excitation order's speed fluctuation below its
// shaft's speed (RequireExcitationWithinSpeed), a tooth load per mesh (from StaticTorqueFlow) of at
// most GearboxLimits::kMaxUnitLoad, and a bounded run (cycles count the first mesh). Throws
// InputError.
void ValidateTrainSpec(const TrainSpec& spec);

// The frequency (Hz) of the first mesh in the file (meshes[0]), whose cycles analysis.cycles,
// transient_cycles and the commands' --cycles and --transient count, at input speed `input_speed`
// (rad/s): z_a |w_a| / 2 pi with |w_a| in proportion to the input speed.
double FirstMeshFrequency(const TrainSpec& spec, const TrainTopology& topology, double input_speed);

// The operating limits of ValidateTrainSpec alone (tooth load per mesh, excitation on each order's
// shaft, run length), for a spec whose names, speed and topology are already valid.
void ValidateTrainLimits(const TrainSpec& spec, const TrainTopology& topology);
// The body excitation order i acts on (its `on` shaft; the input shaft when empty), and its order
// of the input shaft's speed: order k |W_s| / W_in.
int ExcitationBody(const TrainSpec& spec, const TrainTopology& topology, size_t order);
double ExcitationOrderOfInput(const TrainSpec& spec, const TrainTopology& topology, size_t order);
// The excitation rules of ValidateTrainLimits: each order's speed fluctuation on its shaft below
// the shaft's speed, as the shaft would swing on its own (a / (k W_s), a = T / J_s for a torque
// order), and one shaft and kind per frequency (within 1e-9 relative).
void RequireExcitationWithinSpeed(const TrainSpec& spec, const TrainTopology& topology);
// Its tooth-load rule alone (every mesh's unit load from StaticTorqueFlow <= kMaxUnitLoad, the
// error at the load sending the mesh most power): what changes with speed when a viscous drag acts.
void RequireTrainToothLoads(const TrainSpec& spec, const TrainTopology& topology);

}  // namespace gearnvh
