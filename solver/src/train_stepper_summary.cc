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
      return OutOfRangeMessage("on mesh " + summary.stopped_on_mesh, summary.stopped_from,
                               summary.out_of_range_gap, summary.out_of_range_limit);
  }
  return os.str();
}

}  // namespace gearnvh
