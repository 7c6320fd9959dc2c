#include "holo/calib/auto_calibration.hpp"

#include <algorithm>
#include <exception>
#include <opencv2/calib3d.hpp>

#include "holo/calib/calibration_session.hpp"

namespace holo::calib {

namespace fs = std::filesystem;

AutoCalibrationReport runAutoCalibration(CalibrationRig& rig, const AutoCalibrationConfig& config,
                                         const fs::path& out_dir, std::ostream& log, bool quiet) {
  CalibrationSession session(rig, config);
  for (int s = 0; s < kMeasuringSteps; ++s) {
    const StepOutcome& outcome = session.measure(static_cast<CalibrationStep>(s), log, quiet);
    if (outcome.exception) {
      log << "not saved: the previous calibration in " << out_dir.string() << " stays in force\n";
      std::rethrow_exception(outcome.exception);
    }
    if (!outcome.passed()) {
      // Later steps build on this one: measuring them would only repeat its failure.
      log << "not saved: step " << s + 1 << " (" << stepTitle(static_cast<CalibrationStep>(s))
          << ") failed, see its hints; the previous calibration in " << out_dir.string()
          << " stays in force\n";
      return session.report();
    }
  }
  session.save(out_dir, log);
  AutoCalibrationReport report = session.report();
  report.saved = true;
  return report;
}

}  // namespace holo::calib
