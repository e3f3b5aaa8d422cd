// No non-finite number reaches an output: every result document is checked before it is printed
// or written. A NaN or infinity is a bug or an unguarded corner of the model, never a result.
#pragma once

#include <cstddef>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace gearnvh::app {

// Throws NonFiniteResult naming the quantity (its JSON path, e.g. "simulate: te.rms is NaN").
void RequireFinite(const nlohmann::json& doc, const std::string& what);

// A quantity that may be undefined (an infinite horizon, no boundary): its value or JSON null.
nlohmann::json FiniteOrNull(double v);

// A result a failed run did not reach (a stopped tier, speed or cell): NaN in the results, null in
// JSON (FiniteOrNull), an empty CSV field (CsvNumber).
inline constexpr double kNoResult = std::numeric_limits<double>::quiet_NaN();

// A CSV field of `precision` significant digits: empty for a result not reached (NaN).
std::string CsvNumber(double v, int precision = 10);

// A result of a point, cell or tier: the number when its run succeeded (`ok`; a NaN there is still
// refused by RequireFinite), else null.
nlohmann::json ResultOrNull(bool ok, double v);
// Read back: null is kNoResult.
double ResultFromJson(const nlohmann::json& j);

// |a - b| / max(|b|, resolution): a result's difference relative to its reference. Below the
// quantity's resolution a difference is measured against the resolution: a TE of 1e-19 m beside
// an exact 0 (a resting train) is no difference, not 1e281.
double RelativeDifference(double a, double b, double resolution);

// The reference of a tier comparison (pair or train rows with ok() and dof): the row with the most
// DOF among those whose run finished; the one with the most DOF when none did.
template <typename Row>
size_t FinestRow(const std::vector<Row>& rows) {
  size_t finest = 0;
  for (size_t i = 0; i < rows.size(); ++i) {
    const Row& f = rows[finest];
    if (rows[i].ok() != f.ok() ? rows[i].ok() : rows[i].dof > f.dof) finest = i;
  }
  return finest;
}

// Resolutions of the compared quantities, far below anything measurable or audible.
inline constexpr double kTeResolution = 1e-12;                  // m: a TE rig resolves ~1 nm
inline constexpr double kImpactEnergyResolution = 1e-12;        // J per cycle: 1 µm/s on 1 kg
inline constexpr double kAngularAccelerationResolution = 1e-6;  // rad/s^2: 3e-8 m/s^2 at 30 mm

}  // namespace gearnvh::app
