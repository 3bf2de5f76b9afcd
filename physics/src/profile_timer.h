#pragma once
/// The step profile's one timing idiom: a lap timer whose every lap adds the wall time since the
/// previous lap to a StepProfile field (ms), so phases split across substeps accumulate.

#include <chrono>

namespace ricochet::physics {

class ProfileTimer {
 public:
  ProfileTimer() : start_(Clock::now()), last_(start_) {}

  /// Adds the ms since the previous lap (or the start) to field_ms.
  void lap(double& field_ms) {
    const Clock::time_point now = Clock::now();
    field_ms += std::chrono::duration<double, std::milli>(now - last_).count();
    last_ = now;
  }
  /// ms since the timer started.
  double total_ms() const {
    return std::chrono::duration<double, std::milli>(Clock::now() - start_).count();
  }

 private:
  using Clock = std::chrono::steady_clock;
  Clock::time_point start_, last_;
};

}  // namespace ricochet::physics
