#include "binding_support.h"

#include <limits>

#include "gearnvh/model/gearbox_spec_limits.h"
#include "gearnvh/model/input_error.h"
#include "gearnvh/model/train_spec.h"
#include "simulate_command.h"
#include "train_command_options.h"

namespace gearnvh::python {

py::array_t<double> Matrix(const std::vector<std::vector<double>>& rows) {
  size_t columns = 0;
  for (const auto& r : rows) columns = std::max(columns, r.size());
  py::array_t<double> out({rows.size(), columns});
  auto m = out.mutable_unchecked<2>();
  for (size_t i = 0; i < rows.size(); ++i) {
    for (size_t j = 0; j < columns; ++j) {
      m(static_cast<py::ssize_t>(i), static_cast<py::ssize_t>(j)) =
          j < rows[i].size() ? rows[i][j] : std::numeric_limits<double>::quiet_NaN();
    }
  }
  return out;
}

py::array_t<double> AxisValues(const AtlasAxis& a) {
  py::array_t<double> v(a.range.points);
  for (int i = 0; i < a.range.points; ++i) v.mutable_at(i) = AxisValue(a, i);
  return v;
}

py::object ToPython(const nlohmann::json& doc) {
  return py::module_::import("json").attr("loads")(doc.dump());
}

void RequirePairRunLength(const GearboxSpec& spec, double lowest_speed, long cycles, long transient,
                          const std::optional<long>& cycles_keyword,
                          const std::optional<long>& transient_keyword, bool recorded_in_memory) {
  if (recorded_in_memory && cycles_keyword && *cycles_keyword > GearboxLimits::kMaxRecordedCycles) {
    throw InputError("cycles", 0, std::to_string(*cycles_keyword),
                     "must be <= " + std::to_string(GearboxLimits::kMaxRecordedCycles) +
                         " (32 samples of every recorded cycle are kept in memory)");
  }
  app::RequireRunLengthOfOptions(TrainOf(spec), lowest_speed, cycles, transient, cycles_keyword,
                                 transient_keyword, gearnvh::OptionNames{""});
}

Tier TierArgument(const py::object& tier, Tier fallback, const std::string& source) {
  if (tier.is_none()) return fallback;
  const std::string text = py::str(tier);
  try {
    return app::ParseTier(text);
  } catch (const InputError& e) {
    throw InputError("tier", 0, "'" + text + "'", e.rule(), source);
  }
}

std::optional<std::string> TierText(const py::object& tier) {
  if (tier.is_none()) return std::nullopt;
  return std::string(py::str(tier));
}

}  // namespace gearnvh::python
