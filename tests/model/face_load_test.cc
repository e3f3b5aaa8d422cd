// The load across the face under misalignment and lead modifications (docs/design.md §2.5).
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <vector>

#include "gearnvh/model/component_model.h"
#include "gearnvh/model/gear_train.h"
#include "gearnvh/model/mesh_pair.h"
#include "gearnvh/model/mesh_stiffness.h"
#include "model/test_specs.h"

namespace gearnvh {
namespace {

using testing::StandardPair;

// One tooth pair of uniform stiffness c' per unit width over a face b, cut into `slices` strips,
// with a linear mismatch f across the face (0 at the face start).
std::vector<ContactElement> UniformFace(double c_prime, double b, double f, int slices) {
  std::vector<ContactElement> elements;
  for (int k = 0; k < slices; ++k) {
    ContactElement e;
    e.stiffness = c_prime * b / slices;
    e.separation = f * k / slices;
    e.spread = f / slices;
    e.slice = k;
    elements.push_back(e);
  }
  return elements;
}

double LoadedWidth(const std::vector<ContactElement>& elements, double delta, double b,
                   int slices) {
  double width = 0.0;
  for (const ContactElement& e : elements) {
    const double over = delta - e.separation;
    width += b / slices * (over <= 0.0 ? 0.0 : std::min(over / e.spread, 1.0));
  }
  return width;
}

// ISO 6336-1's closed forms for a linear mismatch f over a face b of uniform stiffness c' under a
// load F: K = 1 + c' f b / (2F) while the whole face carries load, sqrt(2 c' f b / F) with a loaded
// width sqrt(2 F b / (c' f)) once part of it opens. The strips integrate (delta - u)_+ exactly over
// a linear u, so both hold to rounding whatever the strip count: 1e-9 relative leaves room for the
// sums over 40 strips (~1e-14 each) and nothing for a discretisation error (the midpoint rule's
// would be ~1/N^2 = 6e-4).
TEST_CASE("a uniform face under a linear mismatch reproduces ISO 6336-1's K_Hbeta in both regimes",
          "[model][face]") {
  const double c_prime = 1.4e10;  // N/m per m of face (14 N/(mm um))
  const double b = 0.03, f = 12e-6;
  const int slices = 40;
  for (double load : {2e4, 4e3, 1e3, 2.0e2}) {
    std::vector<ContactElement> elements = UniformFace(c_prime, b, f, slices);
    const double delta = ShareLoad(elements, load);
    const std::vector<double> line = LineLoadAtSliceEdges(elements, delta, slices, b);
    const double factor = line.front() / (load / b);
    const double x = c_prime * f * b / (2.0 * load);
    INFO("F = " << load << " N, c' f b / (2F) = " << x);
    double shares = 0.0, tangent = 0.0;
    for (const ContactElement& e : elements) shares += e.load_share, tangent += e.tangent;
    CHECK(shares == Approx(1.0).epsilon(1e-12));
    const double width = LoadedWidth(elements, delta, b, slices);
    // The tangent stiffness is c' times the loaded width.
    CHECK(tangent == Approx(c_prime * width).epsilon(1e-12));
    // The edge carries the peak.
    for (double w : line) CHECK(w <= line.front() * (1.0 + 1e-14));
    if (x <= 1.0) {
      CHECK(factor == Approx(1.0 + x).epsilon(1e-9));
      CHECK(delta == Approx(load / (c_prime * b) + 0.5 * f).epsilon(1e-9));
      CHECK(width == Approx(b).epsilon(1e-12));
    } else {
      CHECK(factor == Approx(std::sqrt(2.0 * c_prime * f * b / load)).epsilon(1e-9));
      CHECK(width == Approx(std::sqrt(2.0 * load * b / (c_prime * f))).epsilon(1e-9));
      CHECK(width < b);
    }
  }
}

TEST_CASE("uniform elements share load as before: k (delta - e)_+ = F solved linearly",
          "[model][face]") {
  // Three elements, separations 0, 1, 5 um: at F the first two carry load.
  std::vector<ContactElement> elements(3);
  const double k[] = {2e8, 3e8, 1e8}, e[] = {0.0, 1e-6, 5e-6};
  for (int i = 0; i < 3; ++i) elements[i].stiffness = k[i], elements[i].separation = e[i];
  const double load = 500.0;
  const double delta = ShareLoad(elements, load);
  CHECK(delta == Approx((load + k[1] * e[1]) / (k[0] + k[1])).epsilon(1e-15));
  CHECK(elements[0].loaded);
  CHECK(elements[1].loaded);
  CHECK_FALSE(elements[2].loaded);
  CHECK(elements[0].tangent == k[0]);
  CHECK(elements[2].tangent == 0.0);
}

bool Warns(const MeshCycle& cycle, const std::string& text) {
  return std::any_of(cycle.warnings.begin(), cycle.warnings.end(),
                     [&](const std::string& w) { return w.find(text) != std::string::npos; });
}

MeshCycle CycleOf(const GearboxSpec& spec) {
  const MeshPair pair = PairOf(spec);
  return ComputeMeshCycle(pair, ComputePairGeometry(pair));
}

TEST_CASE("a zero misalignment and empty leads leave the mesh cycle unchanged bitwise",
          "[model][face]") {
  GearboxSpec spec = StandardPair(31, 47, 3e-3, 30e-3);
  spec.operating.torque = 200.0;
  const MeshCycle plain = CycleOf(spec);
  spec.mesh.misalignment = 0.0;
  spec.pinion.lead = LeadModification{};
  const MeshCycle same = CycleOf(spec);
  REQUIRE(same.drive.size() == plain.drive.size());
  for (size_t i = 0; i < plain.drive.size(); ++i) {
    CHECK(same.drive[i].stiffness == plain.drive[i].stiffness);
    CHECK(same.drive[i].lste == plain.drive[i].lste);
    CHECK(same.back[i].stiffness == plain.back[i].stiffness);
  }
  CHECK_FALSE(same.face.modelled());
  CHECK(same.face.factor == 1.0);
}

TEST_CASE("a misaligned spur mesh: K_Hbeta from its own stiffness, stiffness and load sharing",
          "[model][face]") {
  GearboxSpec spec = StandardPair(31, 47, 3e-3, 30e-3);
  spec.operating.torque = 300.0;
  const MeshCycle aligned = CycleOf(spec);
  spec.mesh.misalignment = 3e-6;
  const MeshCycle tilted = CycleOf(spec);
  REQUIRE(tilted.face.modelled());
  const double b = 30e-3, load = tilted.load;
  double mean_stiffness = 0.0;
  for (const FlankSample& d : tilted.drive) mean_stiffness += d.stiffness / tilted.drive.size();
  // Whole face loaded at every sample: the line load at the face start is F/b + k(tau) f / (2b),
  // so the cycle mean gives K = 1 + k_mean f / (2F) with the tangent stiffness' mean. Only pairs
  // entering or leaving are loaded over part of the face, so the form holds to ~1e-3.
  REQUIRE(tilted.face.loaded_width > 0.5 * b);
  const double expected = 1.0 + mean_stiffness * 3e-6 / (2.0 * load);
  INFO("K_Hbeta " << tilted.face.factor << ", from k_mean " << expected << ", ISO method C "
                  << tilted.face.iso_method_c);
  CHECK(tilted.face.factor == Approx(expected).epsilon(2e-3));
  CHECK(tilted.face.factor > 1.05);
  // ISO's c_gamma_beta is 0.85 of the full face's mean stiffness: x scales alike.
  CHECK((tilted.face.iso_method_c - 1.0) / (tilted.face.factor - 1.0) ==
        Approx(0.85).epsilon(5e-3));
  CHECK(tilted.face.linear_mismatch == 3e-6);
  // The cycle-mean line load integrates to F over the face (trapezoid on a linear distribution).
  double integral = 0.0;
  for (size_t i = 0; i + 1 < tilted.face.position.size(); ++i) {
    integral += 0.5 * (tilted.face.line_load[i] + tilted.face.line_load[i + 1]) *
                (tilted.face.position[i + 1] - tilted.face.position[i]);
  }
  CHECK(integral == Approx(load).epsilon(1e-3));
  // The mean approach grows by f / 2 where every loaded pair carries load over the whole face
  // (the uniform-face closed form above); pairs entering and leaving load part of it and shift
  // the mean by a few percent of that, hence 5 %. The shares still sum to 1.
  double lste_aligned = 0.0, lste_tilted = 0.0;
  for (size_t i = 0; i < aligned.drive.size(); ++i) {
    lste_aligned += aligned.drive[i].lste / aligned.drive.size();
    lste_tilted += tilted.drive[i].lste / tilted.drive.size();
    double shares = 0.0;
    for (int m = 0; m < tilted.drive[i].pair_count; ++m)
      shares += tilted.drive[i].pairs[m].load_share;
    CHECK(shares == Approx(1.0).epsilon(1e-12));
  }
  CHECK(lste_tilted - lste_aligned == Approx(1.5e-6).epsilon(0.05));
}

TEST_CASE(
    "a helix slope correction matching the misalignment restores the aligned mesh, and "
    "crowning relieves the edge",
    "[model][face]") {
  GearboxSpec spec = StandardPair(31, 47, 3e-3, 30e-3);
  spec.operating.torque = 300.0;
  const MeshCycle aligned = CycleOf(spec);
  spec.mesh.misalignment = 20e-6;  // opens part of the face at 300 N m
  const MeshCycle tilted = CycleOf(spec);
  CHECK(tilted.face.loaded_width < 0.03);
  CHECK(tilted.face.factor > 2.0);
  // Crowning moves the peak off the edge: a lower K_Hbeta at this large tilt.
  spec.pinion.lead = LeadModification{.crowning = 10e-6};
  const MeshCycle crowned = CycleOf(spec);
  INFO("K_Hbeta tilted " << tilted.face.factor << ", crowned " << crowned.face.factor);
  CHECK(crowned.face.factor < tilted.face.factor);
  // The slope modification removes the tilt: the face is uniform again, as aligned, and no warning
  // says the misalignment is not applied.
  spec.pinion.lead = LeadModification{.slope = -20e-6};
  const MeshCycle corrected = CycleOf(spec);
  CHECK(corrected.face.factor == 1.0);
  CHECK(corrected.face.model == FaceLoad::Model::kUniform);
  CHECK(corrected.face.linear_mismatch == Approx(0.0).margin(1e-18));
  CHECK(corrected.warnings.empty());
  for (size_t i = 0; i < aligned.drive.size(); ++i) {
    CHECK(corrected.drive[i].stiffness == Approx(aligned.drive[i].stiffness).epsilon(1e-12));
    CHECK(corrected.drive[i].lste == Approx(aligned.drive[i].lste).epsilon(1e-12));
  }
}

TEST_CASE("an unloaded mesh keeps its full face and says the misalignment is not applied",
          "[model][face]") {
  GearboxSpec spec = StandardPair(31, 47, 3e-3, 30e-3);
  spec.operating.torque = 0.0;
  spec.mesh.misalignment = 10e-6;
  const MeshCycle cycle = CycleOf(spec);
  CHECK_FALSE(cycle.face.modelled());
  CHECK(cycle.face.model == FaceLoad::Model::kUnloaded);
  CHECK(Warns(cycle, "carries no static load"));
}

// A crowning's vertex against a small slope leaves one strip with a spread at the rounding of the
// mismatch (1e-22 m): its k / s would swamp the sweep's curvature. Such a strip counts as uniform,
// so the mesh is continuous in the misalignment: 1e-6 of a µm more moves the mean stiffness and
// LSTE by ~1e-7 relative (tolerance 1e-5), not by the percents a swamped sweep gave.
TEST_CASE("the face model is continuous where a strip's spread vanishes to rounding",
          "[model][face]") {
  GearboxSpec spec = StandardPair(31, 47, 3e-3, 30e-3);
  spec.operating.torque = 200.0;
  spec.pinion.lead = LeadModification{.crowning = 10e-6};
  const auto summary = [&](double misalignment) {
    spec.mesh.misalignment = misalignment;
    return testing::MeshSummaryOf(spec);
  };
  const MeshStiffnessSummary a = summary(-1e-6), b = summary(-1.000001e-6);
  CHECK(a.mean == Approx(b.mean).epsilon(1e-5));
  CHECK(a.lste_peak_to_peak == Approx(b.lste_peak_to_peak).epsilon(1e-5));
  CHECK(a.face_load_factor == Approx(b.face_load_factor).epsilon(1e-5));
  // The sharing still balances the load at every sample.
  const MeshCycle cycle = CycleOf(spec);
  for (const FlankSample& d : cycle.drive) {
    double shares = 0.0;
    for (int m = 0; m < d.pair_count; ++m) shares += d.pairs[m].load_share;
    CHECK(shares == Approx(1.0).epsilon(1e-12));
  }
}

// A lightly loaded mesh (a loose gear under drag) carries its static load on a sliver of the
// face: the mesh stiffness is that of the static load, which a warning says.
TEST_CASE(
    "a mesh loaded on a small part of its face warns that its stiffness is the static "
    "load's",
    "[model][face]") {
  GearboxSpec spec = StandardPair(31, 47, 3e-3, 30e-3);
  spec.operating.torque = 0.3;
  spec.mesh.misalignment = 10e-6;
  const MeshCycle cycle = CycleOf(spec);
  REQUIRE(cycle.face.modelled());
  CHECK(cycle.face.loaded_width < 0.1 * 30e-3);
  CHECK(Warns(cycle, "of its 30 mm face"));
}

// A pinion on a simply supported elastic shaft (bearings at both ends, rigid radially, free to
// tilt) and a wheel on rigid supports: the mesh force P pushes the pinion away from the wheel, so
// its face tilts by the Euler-Bernoulli slope at the load, P a c (c - a) / (3 E I L) (a, c the
// spans either side), which the Timoshenko elements' section rotation reproduces exactly for a
// point load at a node (a statically determinate beam's moment is independent of shear). The
// bearings' radial compliance (1e14 N/m) tilts it by ~1e-7 of that. The face opens toward the
// longer span, the larger z.
TEST_CASE("the shafts' static deflection tilts the face by the beam's closed-form slope",
          "[model][face]") {
  GearboxSpec spec = StandardPair(31, 47, 3e-3, 30e-3);
  spec.operating.torque = 200.0;
  const double d = 0.03, length = 0.3, a = 0.1, c = length - a;
  ShaftSpec shaft;
  shaft.material = "steel";
  shaft.segments = {{length, d, 0.0}};
  shaft.gear_at = a;
  shaft.bearings = {{0.0, 1e14, 1e8, 0.0, 0.0}, {length, 1e14, 0.0, 0.0, 0.0}};
  shaft.element_length = 0.01;
  spec.input_shaft = shaft;
  const ComponentModel model = BuildComponentModel(spec);
  const double load = model.cycle.load;
  const double ei = 206e9 * std::numbers::pi * std::pow(d, 4) / 64.0;
  const double slope = load * a * c * (c - a) / (3.0 * ei * length);
  INFO("f_sh " << model.cycle.face.shaft_misalignment * 1e6 << " um, closed form "
               << 30e-3 * slope * 1e6 << " um");
  CHECK(model.cycle.face.shaft_misalignment == Approx(30e-3 * slope).epsilon(1e-6));
  CHECK(model.cycle.face.modelled());
  CHECK(model.cycle.face.factor > 1.0);
  // The same gearbox as a one-mesh train: its own structure gives the same tilt and face load, to
  // the conditioning of the static solve (1e14 N/m bearings against ~1e7 N/m of shaft bending
  // leave ~1e-8 of rounding in either solve).
  const GearTrain train = BuildGearTrain(TrainOf(spec));
  const FaceLoad& face = train.meshes[0].cycle.face;
  CHECK(face.shaft_misalignment == Approx(model.cycle.face.shaft_misalignment).epsilon(1e-6));
  CHECK(face.factor == Approx(model.cycle.face.factor).epsilon(1e-6));
  CHECK(train.meshes[0].stiffness.mean == Approx(model.mesh_summary.mean).epsilon(1e-6));
}

}  // namespace
}  // namespace gearnvh
