// Per-mesh and per-loose-gear results of a train run (docs/results.md, "Gear trains").
//
// Exact (from the located events and the state durations, no time grid): impacts per flank
// (free -> drive, free -> back), separations (contact -> free), the fraction of time a mesh is
// free, impact velocities |g'| at the impact instants. Exact as well (as the pair's ExactRecorder,
// solver/exact_recorder.h): the stepper hands over every piece (the state at its start, its tuple,
// start and length); the piece is cut into chunks no longer than the tuple's sub-step D
// (rho(A) D <= 1/2), and on a chunk each output is the polynomial y(s) = sum_{k<=18} r A^k z_c
// s^k / k! (truncation (rho s)^19 / 19! ~ 1e-23, below rounding), whose integrals of y and y^2 are
// closed forms and whose extrema are certified (polynomial_statistics.h). Outputs per mesh: the TE
// delta_i = v_i^T x (mean, RMS about the mean, peak-to-peak), the mesh force k (g) + c delta' in
// contact, 0 free (mean and maximum); per loose gear its impacts and their energy (below) and its
// rattle index, the RMS of its angular acceleration about the mean (rad/s^2). Nothing is taken
// from samples: a peak between samples,
// such as an impact's force, is found. Uniform samples (samples_per_cycle per cycle of the fastest
// mesh, each the exact state at its time) are counted and serve the spectra.
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <cstddef>
#include <string>
#include <vector>

#include "gearnvh/solver/train_tables.h"
#include "gearnvh/solver/trajectory.h"

namespace gearnvh {

struct TrainMeshStatistics {
  std::string name;
  double te_mean = 0.0, te_rms = 0.0, te_peak_to_peak = 0.0;  // m (RMS about the mean)
  double force_mean = 0.0, force_max = 0.0;                   // N
  long drive_impacts = 0, back_impacts = 0, separations = 0, grazing = 0;
  double free_time_fraction = 0.0;                              // [0, 1]
  double impact_velocity_max = 0.0, impact_velocity_rms = 0.0;  // m/s
  double impact_energy = 0.0;  // J: the sum over impacts of (1/2) m_e g'^2 (m_e the mesh's
                               // effective mass, TrainMeshTable::effective_mass)
};

// A loose gear's rattle, over the impacts of the meshes it belongs to (docs/results.md). Ranked by
// impact energy per second, the impacts' kinetic energy along the line of action: what makes the
// noise. A gear without an impact does not rattle and has rank 0 (RMS acceleration alone favours
// light gears that only whine).
struct TrainLooseGearStatistics {
  std::string name;
  int body = 0;
  double rattle_index = 0.0;  // RMS angular acceleration about the mean, rad/s^2
  long drive_impacts = 0, back_impacts = 0;
  long impacts = 0;                                                    // drive + back
  double drive_impacts_per_second = 0.0, back_impacts_per_second = 0.0;  // per recorded second
  double impact_velocity_rms = 0.0, impact_velocity_max = 0.0;  // m/s
  double impact_energy_per_second = 0.0;                        // W (J per recorded second)
  int rank = 0;  // 1 = largest impact energy per second; 0 = no impact
};

// One located contact change of a train run: the mesh, and the pair's record of it (the time, the
// states before and after, the rate of the gap crossing its wall).
struct TrainEventRecord {
  int mesh = 0;
  EventRecord event;
};

// The gear of that name in `gears` (listed by rank), or null.
inline const TrainLooseGearStatistics* FindLooseGear(
    const std::vector<TrainLooseGearStatistics>& gears, const std::string& name) {
  const auto g = std::find_if(gears.begin(), gears.end(),
                              [&](const TrainLooseGearStatistics& l) { return l.name == name; });
  return g == gears.end() ? nullptr : &*g;
}

// One output's exact statistics over the recorded window (from the polynomial pieces, as the TE's).
struct TrainOutputSummary {
  double mean = 0.0, rms = 0.0;  // RMS about the mean
  double min = 0.0, max = 0.0;   // certified extrema
};

// A multi-stage coupling's stage s >= 2 (TrainMeshTable::stage): how often the twist entered it
// and for how long it stayed, on either side of zero.
struct TrainCouplingStageStatistics {
  std::string name;  // "clutch stage 2"
  int coupling = 0;  // GearTrain::couplings
  int stage = 0;
  long entries = 0;  // the twist crossing into the stage (|th| rising past from_s)
  long positive_entries = 0, negative_entries = 0;  // past +from_s (drive), past -from_s
  double engaged_fraction = 0.0;  // of the recorded time, [0, 1]
};

struct TrainStatistics {
  double recorded_time = 0.0;  // s
  long samples = 0;
  std::vector<TrainMeshStatistics> meshes;  // the gear meshes, in the order of the file
  std::vector<TrainCouplingStageStatistics> coupling_stages;
  std::vector<TrainLooseGearStatistics> loose_gears;  // by rank, then the gears without impact
  // With TrainRecorder::TrackBearingForces, per bearing force row (TrainTables::
  // bearing_force_rows: x, y, z of each bearing) its force on the housing, N; empty otherwise.
  std::vector<TrainOutputSummary> bearing_forces;
  // With TrainRecorder::TrackOutputs, per row of its matrix (in order); empty otherwise.
  std::vector<TrainOutputSummary> outputs;
};

class TrainRecorder {
 public:
  // Records from `start_time` on, with samples_per_cycle (>= 1) samples per cycle of the fastest
  // mesh.
  TrainRecorder(const TrainTables& tables, int samples_per_cycle, double start_time);
  double next_sample() const { return next_; }
  double start_time() const { return start_; }  // s
  double sample_interval() const { return dt_; }
  // Keeps the TE of every mesh at the samples at or after `from_time` (s), at most `max_samples`
  // per mesh; with `histories`, also each mesh's force (k (g) + c delta' in contact, 0 free, as
  // the statistics define it) and contact state there.
  // Also the first `tracked_rows` tracked rows' values (TrackBearingForces, TrackOutputs: call
  // them first; at most all of them). Storage is reserved here, so recording allocates nothing.
  void KeepSeries(double from_time, long max_samples, bool histories = false,
                  Eigen::Index tracked_rows = 0);
  // What KeepSeries(_, max_samples, histories, tracked_rows) reserves on a train of `meshes`
  // meshes.
  static size_t SeriesBytes(size_t meshes, long max_samples, bool histories = false,
                            size_t tracked_rows = 0) {
    const size_t per_sample =
        sizeof(double) + (histories ? sizeof(double) + sizeof(ContactState) : 0);
    const size_t samples = static_cast<size_t>(std::max(0L, max_samples));
    return meshes * samples * per_sample + tracked_rows * samples * sizeof(double);
  }
  // Per mesh (file order) the kept TE samples, m; with histories, the force (N) and the contact
  // state at the same samples (empty otherwise).
  const std::vector<std::vector<double>>& te_series() const { return te_series_; }
  const std::vector<std::vector<double>>& force_series() const { return force_series_; }
  const std::vector<std::vector<ContactState>>& contact_series() const { return contact_series_; }
  // Per tracked row (the bearing force rows first, then TrackOutputs's, in order) its kept
  // samples; empty unless KeepSeries kept them.
  const std::vector<std::vector<double>>& tracked_series() const { return tracked_series_; }
  // Moves the kept series out (the recorder keeps none after): a run's histories without a copy.
  void TakeSeries(std::vector<std::vector<double>>& te, std::vector<std::vector<double>>& force,
                  std::vector<std::vector<ContactState>>& contact,
                  std::vector<std::vector<double>>& tracked);
  // From now on, also the exact statistics of every bearing force row (TrainTables::
  // bearing_force_rows; TrainStatistics::bearing_forces). Storage is reserved here.
  void TrackBearingForces();
  // From now on, also the exact statistics of each row of `rows` (m columns: any linear output
  // r^T z, e.g. a coupling's twist or torque; TrainStatistics::outputs), plus for each
  // ContactTerm the contact's force (as the mesh force: k (g) + c delta' in contact, 0 free) times
  // its factor: a multi-stage coupling's torque adds its stages. Storage is reserved here.
  struct ContactTerm {
    Eigen::Index row = 0;  // in `rows`
    int contact = 0;       // TrainTables::meshes
    double factor = 1.0;
  };
  void TrackOutputs(const Eigen::MatrixXd& rows, const std::vector<ContactTerm>& terms = {});
  // Keeps the first `max_events` contact changes of the recorded window, in the order they are
  // located (storage reserved here, so recording allocates nothing).
  void KeepEvents(long max_events);
  const std::vector<TrainEventRecord>& events() const { return events_; }
  // The contact changes of the recorded window, kept or not.
  long window_events() const { return window_events_; }
  // The trajectory from z (at `start`, in `system`, the tuple of `segments` and `states`) for
  // `length` seconds: the exact statistics of its part inside the recorded window.
  void Piece(const TrainSystem& system, const Eigen::Ref<const Eigen::VectorXd>& z, double start,
             double length, const std::vector<int>& segments,
             const std::vector<ContactState>& states);
  // The exact state z at the sample time next_sample(), in the tuple of `segments` and `states`:
  // counted, and its TE (with histories: force and contact) kept (KeepSeries).
  void Sample(double time, const Eigen::VectorXd& z, const std::vector<int>& segments,
              const std::vector<ContactState>& states);
  void Interval(double start, double length, const std::vector<ContactState>& states);
  void Event(int mesh, ContactState from, ContactState to, double time, double rate);
  void Grazing(int mesh, double time);
  TrainStatistics Result() const;

 private:
  static constexpr int kTerms = 18;  // as the pair's ExactRecorder
  // Taylor columns A^k z / k! of the current chunk start, and the state moved by `tau` on them.
  void TaylorColumns(const TrainSystem& system, const Eigen::VectorXd& z);
  void MoveOnColumns(double tau, Eigen::VectorXd& z) const;
  void Chunk(double start, double length, const std::vector<int>& segments,
             const std::vector<ContactState>& states);
  double ForceAt(size_t mesh, const Eigen::VectorXd& z, int segment, ContactState state) const;
  const TrainTables& t_;
  double start_ = 0.0, dt_ = 0.0, next_ = 0.0;
  long samples_ = 0;
  double recorded_ = 0.0;
  double exact_duration_ = 0.0;
  std::vector<OutputStatistics> te_, force_, acceleration_;  // per mesh, mesh, body
  Eigen::MatrixXd taylor_;
  Eigen::VectorXd chunk_z_;
  // A chunk's polynomial coefficients as products, not one dot product per mesh and term: every
  // mesh's TE row (and back-flank row) and every loose body's angle row, times the Taylor columns.
  // Row-major, so a row is one polynomial's contiguous coefficients.
  using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  RowMatrix te_rows_, back_rows_, loose_rows_;
  RowMatrix te_coefficients_, back_coefficients_, acceleration_coefficients_;
  std::vector<int> loose_bodies_;
  std::vector<double> free_time_, impact_sum2_, impact_max_;
  std::vector<long> drive_impacts_, back_impacts_, separations_, grazing_;
  double keep_from_ = 0.0;
  long keep_max_ = 0;
  bool keep_histories_ = false;
  std::vector<std::vector<double>> te_series_, force_series_;
  std::vector<std::vector<ContactState>> contact_series_;
  std::vector<std::vector<double>> tracked_series_;
  Eigen::VectorXd tracked_values_;
  // The tracked rows on the whole state: the bearing force rows (TrainTables::
  // bearing_force_rows, TrackBearingForces) first, then TrackOutputs's; their chunk coefficients
  // and statistics.
  RowMatrix tracked_rows_, tracked_coefficients_;
  std::vector<ContactTerm> contact_terms_;  // rows counted in tracked_rows_
  std::vector<OutputStatistics> tracked_;
  Eigen::Index bearing_rows_ = 0;
  void Track(const RowMatrix& rows, Eigen::Index at);
  long keep_events_ = 0, window_events_ = 0;
  std::vector<TrainEventRecord> events_;
};

}  // namespace gearnvh
