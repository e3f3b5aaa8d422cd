#include <numbers>
#include <sstream>

#include "gearnvh/solver/train_stepper.h"

namespace gearnvh {

const char* TrainStepperInfoName(TrainStepperSummary::Info info) {
  switch (info) {
    case TrainStepperSummary::Info::kSuccess:
      return "success";
    case TrainStepperSummary::Info::kTooManyEvents:
      return "too many events";
    case TrainStepperSummary::Info::kOutOfRange:
      return "out of range";
  }
  return "?";
}

std::string TrainStepperMessage(const TrainStepperSummary& summary) {
  std::ostringstream os;
  switch (summary.info) {
    case TrainStepperSummary::Info::kSuccess:
      break;
    case TrainStepperSummary::Info::kTooManyEvents:
      // The start to 10 digits: grid segments can be ~1e-9 of the run's time long.
      os.precision(3);
      os << "more than " << summary.event_limit << " contact events in the "
         << summary.stopped_to - summary.stopped_from << " s grid segment starting at t = ";
      os.precision(10);
      os << summary.stopped_from << " s";
      if (!summary.stopped_on_mesh.empty()) os << "; the last on mesh " << summary.stopped_on_mesh;
      break;
    case TrainStepperSummary::Info::kOutOfRange:
      if (summary.out_of_range_twist) {
        os.precision(4);
        os << "on " << summary.stopped_on_mesh << " (t = " << summary.stopped_from
           << " s) the coupling's twist passed its stage wall by "
           << summary.out_of_range_gap * 180.0 / std::numbers::pi << " deg, more than "
           << summary.out_of_range_limit * 180.0 / std::numbers::pi
           << " deg: the response grows without bound at this operating point and tier, and no "
              "torsional spring twists that far; the run stopped there";
        break;
      }
      return OutOfRangeMessage("on mesh " + summary.stopped_on_mesh, summary.stopped_from,
                               summary.out_of_range_gap, summary.out_of_range_limit);
  }
  return os.str();
}

}  // namespace gearnvh
