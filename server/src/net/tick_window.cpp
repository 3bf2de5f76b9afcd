#include "tick_window.h"

#include <algorithm>
#include <cmath>

namespace ricochet::server {

void TickWindow::record(double seconds) {
  samples_[next_] = seconds;
  next_ = (next_ + 1) % samples_.size();
  filled_ = std::min(filled_ + 1, samples_.size());
}

std::array<double, 4> TickWindow::quantiles() const {
  if (filled_ == 0) return {0, 0, 0, 0};
  std::vector<double> sorted(samples_.begin(),
                             samples_.begin() + static_cast<std::ptrdiff_t>(filled_));
  std::sort(sorted.begin(), sorted.end());
  const auto rank = [&sorted](double p) {
    const double index = std::ceil(p * static_cast<double>(sorted.size()));
    return sorted[static_cast<std::size_t>(std::max(index, 1.0)) - 1];
  };
  return {rank(0.50), rank(0.95), rank(0.99), sorted.back()};
}

}  // namespace ricochet::server
