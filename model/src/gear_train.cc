#include "gearnvh/model/gear_train.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "gearnvh/model/component_model.h"
#include "gearnvh/model/gearbox_spec_limits.h"
#include "gearnvh/model/input_error.h"
#include "gearnvh/model/shaft_misalignment.h"
#include "gearnvh/model/train_structure.h"

namespace gearnvh {
namespace {

// Polar inertia of an elastic shaft's tubes and lumped bodies.
double ShaftPolarInertia(const ShaftSpec& shaft, const Material& material) {
  double j = 0.0;
  for (const ShaftSegment& s : shaft.segments) {
    const double d4 = std::pow(s.outer_diameter, 4) - std::pow(s.inner_diameter, 4);
    j += material.density * std::numbers::pi / 32.0 * d4 * s.length;
  }
  for (const LumpedInertia& l : shaft.inertias) j += l.polar;
  return j;
}

// The mesh's schema-1 gearbox, pair and geometry at the body speeds of `topology`.
void SetMeshKinematics(const TrainSpec& spec, const TrainTopology& topology, size_t m,
                       TrainMeshModel& mesh) {
  mesh.gearbox = MeshGearbox(spec, topology, static_cast<int>(m), mesh.transmitted_torque);
  mesh.pair = PairOf(mesh.gearbox);
  mesh.pair.path_a = "gears." + spec.gears[static_cast<size_t>(mesh.gear_a)].name;
  mesh.pair.path_b = "gears." + spec.gears[static_cast<size_t>(mesh.gear_b)].name;
  mesh.pair.path_mesh = "meshes[" + std::to_string(m) + "]";
  mesh.geometry = ComputePairGeometry(mesh.pair);
}

// The mesh's cycle, segments and stiffness summary for its pair.
void BuildMeshCycle(const TrainSpec& spec, const MeshStiffnessOptions& options,
                    TrainMeshModel& mesh) {
  mesh.cycle = ComputeMeshCycle(mesh.pair, mesh.geometry, options);
  try {
    mesh.segmentation = SegmentMeshCycle(mesh.pair, MeshEvaluator(mesh.pair, mesh.geometry),
                                         spec.analysis.segments_per_cycle);
  } catch (const InputError& e) {  // the rule names "this pair": say which mesh it is
    throw e.Renamed([](const std::string& path) { return path; },
                    [&](const std::string& rule) {
                      return rule + " in " + mesh.pair.path_mesh + " (" + mesh.name + ")";
                    });
  }
  mesh.stiffness = SummarizeMeshCycle(mesh.cycle, mesh.geometry, mesh.segmentation);
}

// Elastic shafts tilt the gears under the static load: each loaded mesh again with the
// misalignment that gives (shaft_misalignment.h). The load sits on the back flank where power
// flows from b to a, so that flank's line of action measures it there.
void ApplyShaftMisalignment(const TrainSpec& spec, const MeshStiffnessOptions& options,
                            GearTrain& train) {
  const bool elastic = std::any_of(spec.shafts.begin(), spec.shafts.end(),
                                   [](const TrainShaft& s) { return s.elastic.has_value(); });
  if (!elastic) return;
  const TrainStructure structure = AssembleTrainStructure(spec, train);
  // Every mesh engaged on its loaded flank (EngagedStiffness takes the drive flank's).
  Eigen::SparseMatrix<double> engaged = structure.K;
  for (size_t m = 0; m < train.meshes.size(); ++m) {
    const TrainMeshVectors& v = structure.meshes[m];
    const Eigen::SparseVector<double> loaded =
        (train.meshes[m].back_flank_loaded ? v.v_back : v.v_drive).sparseView();
    engaged +=
        structure.mean_stiffness[m] * Eigen::SparseMatrix<double>(loaded * loaded.transpose());
  }
  const Eigen::VectorXd x =
      StaticDeflection(engaged, structure.static_force, structure.free_rotations);
  for (size_t m = 0; m < train.meshes.size(); ++m) {
    TrainMeshModel& mesh = train.meshes[m];
    if (!(mesh.cycle.load > 0.0)) continue;
    const TrainMeshVectors& v = structure.meshes[m];
    // v_back's approach is negative in back contact (structure_assembly.h): its compression is
    // -v_back^T x, so its face opens the other way round.
    const double tilt = TiltMisalignment(mesh.back_flank_loaded ? v.v_back : v.v_drive, x,
                                         structure.gear_node[static_cast<size_t>(mesh.gear_a)],
                                         structure.gear_node[static_cast<size_t>(mesh.gear_b)],
                                         mesh.pair.face_width);
    mesh.pair.shaft_misalignment = mesh.back_flank_loaded ? -tilt : tilt;
    if (mesh.pair.shaft_misalignment != 0.0) BuildMeshCycle(spec, options, mesh);
  }
}

}  // namespace

std::vector<double> BodyInertias(const TrainSpec& spec, const TrainTopology& topology) {
  std::vector<double> inertia(topology.bodies.size(), 0.0);
  for (size_t b = 0; b < topology.bodies.size(); ++b) {
    const TrainBody& body = topology.bodies[b];
    if (body.kind == BodyKind::kShaft) {
      const TrainShaft& s = spec.shafts[static_cast<size_t>(body.shaft)];
      inertia[b] = s.elastic ? ShaftPolarInertia(*s.elastic, spec.materials.at(s.elastic->material))
                             : s.inertia.value_or(0.0);
    }
    for (int g : body.gears) {
      const GearSpec& gear = spec.gears[static_cast<size_t>(g)].gear;
      inertia[b] += DiskBody(gear, spec.materials.at(gear.material)).polar;
    }
  }
  return inertia;
}

GearTrain BuildGearTrain(const TrainSpec& spec, const MeshStiffnessOptions& options) {
  GearTrain train;
  train.topology = AnalyseTrainTopology(spec);
  const TrainTopology& topo = train.topology;
  train.body_inertia = BodyInertias(spec, topo);

  const TrainTorqueFlow flow = StaticTorqueFlow(spec, topo);
  train.input_torque = flow.input_torque;
  for (size_t m = 0; m < spec.meshes.size(); ++m) {
    TrainMeshModel mesh;
    mesh.name = spec.meshes[m].Name();
    mesh.gear_a = spec.GearIndex(spec.meshes[m].gear_a);
    mesh.gear_b = spec.GearIndex(spec.meshes[m].gear_b);
    mesh.body_a = topo.gear_body[static_cast<size_t>(mesh.gear_a)];
    mesh.body_b = topo.gear_body[static_cast<size_t>(mesh.gear_b)];
    mesh.in_loop = std::find(topo.loop_meshes.begin(), topo.loop_meshes.end(),
                             static_cast<int>(m)) != topo.loop_meshes.end();
    mesh.transmitted_torque = flow.transmitted_torque[m];
    mesh.back_flank_loaded = flow.back_flank_loaded[m];
    train.meshes.push_back(mesh);
  }
  for (size_t c = 0; c < spec.couplings.size(); ++c) {
    const TrainCoupling& coupling = spec.couplings[c];
    TrainCouplingModel model;
    model.name = coupling.name;
    model.body_a = spec.ShaftIndex(coupling.shaft_a);  // a shaft's body is its index
    model.body_b = spec.ShaftIndex(coupling.shaft_b);
    model.stiffness = coupling.stiffness;
    model.stages = coupling.stages;
    model.damping = coupling.damping;
    model.mean_torque = flow.coupling_torque[c];
    // Past ~15 deg no clutch-damper stage or halfshaft is linear: most often a stiffness written
    // per radian that was meant per degree (57x too soft). A dual-mass flywheel's arc springs may
    // twist further, so this warns and does not refuse.
    constexpr double kPlausibleTwist = 15.0 * std::numbers::pi / 180.0;
    if (model.stages.empty() && std::abs(model.MeanTwist()) > kPlausibleTwist) {
      train.warnings.push_back(fmt::format(
          "coupling '{}': the static twist {:.4g} deg ({:.4g} N m over {:.4g} N m/rad) is past "
          "the 15 deg a clutch-damper stage or a halfshaft stays linear over: is the stiffness's "
          "unit right (N*m/deg is 57.3 times N*m/rad)? (A dual-mass flywheel's arc springs may "
          "twist further.)",
          model.name, model.MeanTwist() * 180.0 / std::numbers::pi, model.mean_torque,
          model.stiffness));
    } else if (!model.stages.empty() &&
               std::abs(model.MeanTwist()) > GearboxLimits::kMaxCouplingStageAngle) {
      train.warnings.push_back(fmt::format(
          "coupling '{}': the static twist {:.4g} deg ({:.4g} N m along its stages) is past 90 "
          "deg, which no torsional spring reaches: are the stiffnesses' units right (N*m/deg is "
          "57.3 times N*m/rad)?",
          model.name, model.MeanTwist() * 180.0 / std::numbers::pi, model.mean_torque));
    }
    train.couplings.push_back(model);
  }

  for (size_t m = 0; m < train.meshes.size(); ++m) {
    TrainMeshModel& mesh = train.meshes[m];
    SetMeshKinematics(spec, topo, m, mesh);
    BuildMeshCycle(spec, options, mesh);
    const bool gears = spec.meshes[m].effective_mass == MeshEffectiveMass::kGears;
    const auto inertia = [&](int gear, int body) {
      const GearSpec& g = spec.gears[static_cast<size_t>(gear)].gear;
      return gears ? DiskBody(g, spec.materials.at(g.material)).polar
                   : train.body_inertia[static_cast<size_t>(body)];
    };
    const double ja = inertia(mesh.gear_a, mesh.body_a), jb = inertia(mesh.gear_b, mesh.body_b);
    const double ra = mesh.geometry.pinion.base, rb = mesh.geometry.wheel.base;
    mesh.effective_mass = ja * jb / (ja * rb * rb + jb * ra * ra);
  }
  ApplyShaftMisalignment(spec, options, train);
  for (TrainMeshModel& mesh : train.meshes) {
    for (const std::string& w : mesh.cycle.warnings) train.warnings.push_back(w);
    if (mesh.back_flank_loaded) {
      train.warnings.push_back(mesh.pair.path_mesh + " (" + mesh.name + "): power flows from " +
                               mesh.pair.path_b + " to " + mesh.pair.path_a +
                               ", so the load is on the back flank; its stiffness is evaluated on "
                               "the drive flank (list the driving gear first to be exact)");
    }
    if (mesh.in_loop) {
      train.warnings.push_back(mesh.pair.path_mesh + " (" + mesh.name +
                               ") closes a kinematic loop: the static torque split is "
                               "indeterminate, and this mesh is analysed unloaded");
    }
  }
  return train;
}

double TrainMeshModel::Damping() const {
  return 2.0 * gearbox.mesh.damping_ratio * std::sqrt(stiffness.mean * effective_mass);
}

GearTrain GearTrainAtSpeed(GearTrain train, const TrainSpec& at) {
  train.topology = AnalyseTrainTopology(at);
  // A viscous drag's mean torque grows with speed: the torque flow, and with it every mesh's load.
  if (DragDampsFreeRotation(at, train.topology)) return BuildGearTrain(at);
  for (size_t m = 0; m < train.meshes.size(); ++m) {
    SetMeshKinematics(at, train.topology, m, train.meshes[m]);
  }
  return train;
}

TrainTorsionalModes TorsionalModes(const GearTrain& train) {
  const int n = static_cast<int>(train.body_inertia.size());
  TrainTorsionalModes out;
  out.M = Eigen::MatrixXd::Zero(n, n);
  out.K = Eigen::MatrixXd::Zero(n, n);
  for (int b = 0; b < n; ++b) out.M(b, b) = train.body_inertia[static_cast<size_t>(b)];
  Eigen::MatrixXd V = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(train.meshes.size()), n);
  for (size_t i = 0; i < train.meshes.size(); ++i) {
    const TrainMeshModel& mesh = train.meshes[i];
    Eigen::VectorXd v = Eigen::VectorXd::Zero(n);
    v(mesh.body_a) += mesh.geometry.pinion.base;
    v(mesh.body_b) -= mesh.geometry.wheel.base;
    out.K += mesh.stiffness.mean * v * v.transpose();
    V.row(static_cast<Eigen::Index>(i)) = v.transpose();
  }
  // Couplings: their twist th_a - th_b, its row scaled like a mesh's (a base radius).
  const double radius = V.rows() > 0 ? V.cwiseAbs().maxCoeff() : 1.0;
  for (const TrainCouplingModel& c : train.couplings) {
    Eigen::VectorXd w = Eigen::VectorXd::Zero(n);
    w(c.body_a) = 1.0;
    w(c.body_b) = -1.0;
    out.K += c.StaticStiffness() * w * w.transpose();
    V.conservativeResize(V.rows() + 1, Eigen::NoChange);
    V.bottomRows(1) = radius * w.transpose();
  }
  // The free rotations are the null space of V (no mesh or coupling sees them): found by the SVD of
  // V, whose entries are base radii, so "zero" is a scale-free 1e-9 of the largest singular value
  // (a numerical zero test on K would have to tell them from the rounding of K, ~eps max K_ii). The
  // elastic modes are those of the pencil restricted to the M-orthogonal complement of that null
  // space. A connected train with every mesh engaged has one: th_j ~ |w_j|.
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(V, Eigen::ComputeFullV);
  int rank = 0;
  for (Eigen::Index i = 0; i < svd.singularValues().size(); ++i) {
    if (svd.singularValues()[i] > 1e-9 * svd.singularValues()[0]) ++rank;
  }
  out.free_rotations = n - rank;
  const Eigen::MatrixXd rigid = svd.matrixV().rightCols(n - rank);
  const Eigen::MatrixXd mr = out.M * rigid;
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(mr);
  const Eigen::MatrixXd q = qr.householderQ() * Eigen::MatrixXd::Identity(n, n);
  const Eigen::MatrixXd t = q.rightCols(rank);
  if (rank > 0) {
    const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(t.transpose() * out.K * t,
                                                                        t.transpose() * out.M * t);
    for (int k = 0; k < rank; ++k) {
      out.frequencies_hz.push_back(std::sqrt(std::max(eig.eigenvalues()(k), 0.0)) /
                                   (2.0 * std::numbers::pi));
    }
    out.shapes = t * eig.eigenvectors();
  }
  return out;
}

}  // namespace gearnvh
