// No non-finite number reaches an output: every result document is checked before it is printed
// or written. A NaN or infinity is a bug or an unguarded corner of the model, never a result.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace gearnvh::app {

// Throws NonFiniteResult naming the quantity (its JSON path, e.g. "simulate: te.rms is NaN").
void RequireFinite(const nlohmann::json& doc, const std::string& what);

// A quantity that may be undefined (an infinite horizon, no boundary): its value or JSON null.
nlohmann::json FiniteOrNull(double v);

// |a - b| / |b|: a result's relative difference to its reference (|b| floored at 1e-300).
double RelativeDifference(double a, double b);

}  // namespace gearnvh::app
