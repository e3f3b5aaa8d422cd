#include "gearnvh/analysis/whine.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <numbers>
#include <optional>
#include <string>

#include "gearnvh/analysis/parallel_for.h"
#include "gearnvh/model/gear_train.h"
#include "gearnvh/model/input_error.h"
#include "gearnvh/model/train_structure.h"
#include "gearnvh/nvh/harmonic_response.h"
#include "gearnvh/reduction/train_reduction.h"
#include "gearnvh/solver/solver_options.h"
#include "whine_inputs.h"
#include "whine_parts.h"

namespace gearnvh {
namespace {

void RequireRange(const OptionNames& names, const char* option, int value, int min, int max) {
  if (value < min || value > max) {
    throw InputError(names(option), 0, std::to_string(value),
                     fmt::format("must be an integer from {} to {}", min, max));
  }
}

// The running angle's row of body b in the tier's coordinates: s_b T(th_z of its node, :).
Eigen::RowVectorXd BodyAngle(const GearTrain& train, const TrainStructure& structure,
                             const TrainReducedModel& reduced, int b) {
  const TrainBody& body = train.topology.bodies[static_cast<size_t>(b)];
  const int node = structure.body_node[static_cast<size_t>(b)];
  const double sense = body.speed > 0.0 ? 1.0 : -1.0;
  return sense * reduced.recovery.row(TrainStructure::Dof(node, kThz));
}

HarmonicModel MeanModel(const GearTrain& train, const TrainStructure& structure,
                        const TrainReducedModel& reduced) {
  HarmonicModel m;
  m.M = reduced.M;
  m.C = reduced.C;
  m.G = reduced.G;
  m.K = reduced.K + CouplingStaticStiffness(structure, reduced);
  for (size_t i = 0; i < train.meshes.size(); ++i) {
    const TrainMeshModel& mm = train.meshes[i];
    const bool back = mm.back_flank_loaded;
    m.mesh_vectors.push_back(back ? reduced.v_back[i] : reduced.v_drive[i]);
    m.te_vectors.push_back(reduced.v_drive[i]);
    m.mesh_stiffness.push_back(back ? CycleMeanStiffness(mm.segmentation, Flank::kBack)
                                    : mm.stiffness.mean);
    m.mesh_damping.push_back(structure.mesh_damping[i]);
  }
  const int bodies = static_cast<int>(train.topology.bodies.size());
  m.body_angles.resize(bodies, reduced.dof);
  for (int b = 0; b < bodies; ++b) m.body_angles.row(b) = BodyAngle(train, structure, reduced, b);
  if (reduced.tier != Tier::kTier1) {
    for (const StructureBearing& b : structure.bearings) {
      const Eigen::MatrixXd point = BearingPointRows(b, reduced);
      const Eigen::Vector3d k(b.radial_stiffness, b.radial_stiffness, b.axial_stiffness);
      m.bearing_stiffness.push_back(k.asDiagonal() * point);
      m.bearing_damping.push_back(b.damping * point);
    }
  }
  return m;
}

WhineResult EmptyResult(const TrainSpec& spec, const GearTrain& train,
                        const TrainStructure& structure, const HarmonicModel& model,
                        const std::vector<WhineLine>& lines, const WhineOptions& options) {
  WhineResult r;
  r.tier = options.tier;
  r.dof = model.dof();
  SweepRange range = spec.analysis.speed_sweep;
  range.points = options.speeds;
  r.speed_scale = range.scale;
  for (int s = 0; s < options.speeds; ++s) r.speed_rad_s.push_back(range.Point(s));
  r.lines = lines;
  const size_t speeds = r.speed_rad_s.size();
  const std::vector<double> zeros(speeds, 0.0);
  const std::vector<std::vector<double>> per_line(lines.size(), zeros);
  for (size_t i = 0; i < train.meshes.size(); ++i) {
    const TrainMeshModel& mm = train.meshes[i];
    r.meshes.push_back({mm.name, model.mesh_stiffness[i], mm.cycle.load, mm.back_flank_loaded,
                        per_line, per_line, zeros, std::vector<bool>(speeds, false)});
  }
  if (!model.bearing_stiffness.empty()) {
    for (const StructureBearing& b : structure.bearings) {
      WhineBearing wb;
      wb.shaft = spec.shafts[static_cast<size_t>(b.shaft)].name;
      wb.index = b.index;
      wb.at = b.at;
      wb.force_amplitude_n.assign(lines.size(), {zeros, zeros, zeros});
      r.bearings.push_back(std::move(wb));
    }
  }
  for (const TrainBody& body : train.topology.bodies) r.bodies.push_back({body.name, per_line});
  return r;
}

std::vector<std::string> Warnings(const TrainSpec& spec, const GearTrain& train,
                                  const WhineOptions& options) {
  std::vector<std::string> w = train.warnings;
  for (size_t i = 0; i < train.meshes.size(); ++i) {
    const TrainMeshModel& mm = train.meshes[i];
    const MeshSpec& mesh = spec.meshes[i].mesh;
    if (mesh.friction_coefficient > 0.0) {
      w.push_back(fmt::format(
          "mesh {}: tooth friction is not in the mean model (it reverses at the pitch point: a "
          "variation over the mesh cycle, as the stiffness's); simulate and sweep include it",
          mm.name));
    }
    if (mesh.damping_ratio == 0.0) {
      w.push_back(fmt::format(
          "mesh {} has no damping: its modes are undamped and their resonances unbounded",
          mm.name));
    }
    if (!(mm.cycle.load > 0.0)) {
      w.push_back(fmt::format(
          "mesh {} carries no static load: the mean model holds it in contact at its mean "
          "stiffness, so it is flagged for contact loss wherever it responds (its rattle is the "
          "time-domain solver's: simulate, sweep)",
          mm.name));
    }
  }
  if (options.tier == Tier::kTier1)
    w.push_back("tier 1 has no lateral DOF: no bearing forces (tier 2 or higher has them)");
  if (options.tier == Tier::kTier2)
    w.push_back("tier 2 has no axial DOF: every bearing's z force is 0 (tier 3 or higher has it)");
  return w;
}

// The result holds per speed and line each mesh's TE and force, each bearing's three forces, each
// body's speed (and the housing's response): refused above 2 GB (100,000 speeds of a
// transmission's hundreds of lines would not fit), naming the options that size it.
void RequireResultFits(const HarmonicModel& model, size_t lines, const WhineOptions& options) {
  const double per_line_and_speed = 2.0 * static_cast<double>(model.mesh_vectors.size()) +
                                    3.0 * static_cast<double>(model.bearing_stiffness.size()) +
                                    static_cast<double>(model.body_angles.rows()) + 1.0;
  const double bytes = per_line_and_speed * static_cast<double>(lines) *
                       static_cast<double>(options.speeds) * sizeof(double);
  constexpr double kLimit = 2e9;
  if (bytes > kLimit) {
    throw InputError(options.names("speeds"), 0, std::to_string(options.speeds),
                     fmt::format("makes a result of {:.1f} GB ({} lines; at most {:.0f} GB): "
                                 "fewer {}, {} or {}",
                                 bytes / 1e9, lines, kLimit / 1e9, options.names("speeds"),
                                 options.names("harmonics"), options.names("sidebands")));
  }
}

// Solves speeds [first, last) into `r`.
void SolveSpeeds(const HarmonicModel& model, const std::vector<HarmonicInput>& inputs,
                 const std::vector<whine::ResolvedCurve>& curves, size_t first, size_t last,
                 const WhineOptions& options, SweepProgressCounter& progress, WhineResult& r) {
  HarmonicSolver solver(model);
  HarmonicResponse out;
  for (size_t s = first; s < last; ++s) {
    ThrowIfCancelled(options.cancel);
    const double speed = r.speed_rad_s[s];
    solver.SetSpeed(speed);
    for (size_t l = 0; l < r.lines.size(); ++l) {
      const double w = r.lines[l].order * speed;
      solver.Solve(w, inputs[l], out);
      if (r.housing) r.housing->acceleration_m_s2[l][s] = whine::HousingResponse(curves, w, out);
      for (size_t i = 0; i < r.meshes.size(); ++i) {
        r.meshes[i].te_amplitude_m[l][s] = std::abs(out.te[i]);
        r.meshes[i].force_amplitude_n[l][s] = std::abs(out.mesh_force[i]);
        r.meshes[i].force_amplitude_sum_n[s] += std::abs(out.mesh_force[i]);
      }
      for (size_t b = 0; b < r.bearings.size(); ++b) {
        for (int d = 0; d < 3; ++d)
          r.bearings[b].force_amplitude_n[l][static_cast<size_t>(d)][s] =
              std::abs(out.bearing_force[b][d]);
      }
      for (size_t b = 0; b < r.bodies.size(); ++b)
        r.bodies[b].speed_amplitude_rad_s[l][s] = std::abs(out.body_speed[b]);
    }
    progress.Tick();
  }
}

}  // namespace

void WhineOptions::Validate() const {
  RequireRange(names, "speeds", speeds, 2, 100000);
  RequireRange(names, "harmonics", mesh_harmonics, 1, 20);
  RequireRange(names, "sidebands", sideband_orders, 0, 10);
  RequireRange(names, "jobs", threads, 0, 1024);
  if (!housing) return;
  for (const HousingCurve& c : housing->curves) {
    const std::string& source = housing->source;
    if (c.direction < 0 || c.direction > 2)
      throw InputError("direction", c.line, std::to_string(c.direction), "must be x, y or z",
                       source);
    if (c.frequency_hz.size() < 2 || c.transfer.size() != c.frequency_hz.size()) {
      throw InputError("frequency_hz", c.line, std::to_string(c.frequency_hz.size()) + " points",
                       "each bearing and direction needs 2 points or more", source);
    }
    for (size_t i = 0; i < c.frequency_hz.size(); ++i) {
      const double f = c.frequency_hz[i];
      if (!(f >= 0.0) || !std::isfinite(f) || (i > 0 && !(f > c.frequency_hz[i - 1]))) {
        throw InputError("frequency_hz", c.line, fmt::format("{:g}", f),
                         "must be finite, >= 0 and strictly ascending per bearing and direction",
                         source);
      }
      if (!std::isfinite(c.transfer[i].real()) || !std::isfinite(c.transfer[i].imag()))
        throw InputError("real/imag", c.line, "not finite", "must be finite numbers", source);
    }
  }
}

int WhineResult::ContactLossSpeeds() const {
  int count = 0;
  for (size_t s = 0; s < speed_rad_s.size(); ++s) {
    for (const WhineMesh& m : meshes) {
      if (m.contact_loss[s]) {
        ++count;
        break;
      }
    }
  }
  return count;
}

WhineResult RunWhine(const TrainSpec& spec, const WhineOptions& options,
                     const WhineProgress& progress) {
  options.Validate();
  // The excitation orders are exact inputs here: the time-domain solver's rule that its grid
  // resolves them (BuildGearTrain's only use of them) does not apply.
  TrainSpec structural = spec;
  structural.operating.excitation.clear();
  const GearTrain train = BuildGearTrain(structural);
  ThrowIfCancelled(options.cancel);
  const TrainStructure structure = AssembleTrainStructure(spec, train);
  const TrainReducedModel reduced = ReduceTrain(structure, options.tier);
  ThrowIfCancelled(options.cancel);
  const HarmonicModel model = MeanModel(train, structure, reduced);

  std::vector<whine::MeshInput> mesh_inputs;
  for (size_t i = 0; i < train.meshes.size(); ++i)
    mesh_inputs.push_back(whine::MeshInputOf(spec, train, i));
  const std::vector<WhineLine> lines = whine::Lines(spec, train, mesh_inputs, options);
  std::vector<HarmonicInput> inputs(lines.size());
  for (size_t l = 0; l < lines.size(); ++l) {
    for (const whine::MeshInput& in : mesh_inputs)
      inputs[l].mesh.push_back(in.Coefficient(lines[l].order));
    inputs[l].body_torque = whine::BodyTorques(spec, train, lines[l].order);
  }

  RequireResultFits(model, lines.size(), options);
  WhineResult r = EmptyResult(spec, train, structure, model, lines, options);
  r.warnings = Warnings(spec, train, options);
  std::vector<whine::ResolvedCurve> curves;
  if (options.housing) {
    curves = whine::ResolveHousing(*options.housing, r);
    r.housing = WhineHousing{options.housing->source,
                             std::vector<std::vector<double>>(
                                 lines.size(), std::vector<double>(r.speed_rad_s.size(), 0.0))};
  }
  const size_t speeds = r.speed_rad_s.size();
  const int workers = ParallelWorkers(speeds, options.threads);
  SweepProgressCounter counter(static_cast<int>(speeds), progress);
  std::vector<std::exception_ptr> failures(static_cast<size_t>(workers));
  ParallelFor(static_cast<size_t>(workers), workers, [&](size_t w) {
    try {
      SolveSpeeds(model, inputs, curves, speeds * w / workers, speeds * (w + 1) / workers, options,
                  counter, r);
    } catch (...) {
      failures[w] = std::current_exception();
    }
  });
  for (const std::exception_ptr& f : failures) {
    if (f) std::rethrow_exception(f);
  }
  for (WhineMesh& m : r.meshes) {
    for (size_t s = 0; s < speeds; ++s)
      m.contact_loss[s] =
          m.force_amplitude_sum_n[s] > 0.0 && m.force_amplitude_sum_n[s] >= m.static_force;
  }
  const double top_hz =
      lines.empty() ? 0.0 : lines.back().order * r.speed_rad_s.back() / (2.0 * std::numbers::pi);
  r.modes = whine::Modes(model, structure, reduced, 1.25 * top_hz);
  r.critical_speeds = whine::CriticalSpeeds(r);
  return r;
}

}  // namespace gearnvh
