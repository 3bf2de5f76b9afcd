#include "tick_window.h"

#include <algorithm>

namespace ricochet::server {

void TickWindow::record(double seconds) {
  samples_[next_] = seconds;
  next_ = (next_ + 1) % samples_.size();
  filled_ = std::min(filled_ + 1, samples_.size());
}

stats::Summary TickWindow::summary() const {
  return stats::summarize(std::vector<double>(
      samples_.begin(), samples_.begin() + static_cast<std::ptrdiff_t>(filled_)));
}

}  // namespace ricochet::server
