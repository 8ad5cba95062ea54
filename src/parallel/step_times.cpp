#include "sphdem/parallel/step_times.hpp"

#include <algorithm>
#include <cmath>

#include "sphdem/parallel/exact_sum.hpp"

namespace sphdem {

StepTimes::StepTimes(std::size_t block) : block_(std::max<std::size_t>(block, 1)) {
  pending_.reserve(block_);
  slowest_.reserve(block_);
}

void StepTimes::reset() {
  pending_.clear();
  histogram_ = {};
  steps_ = 0;
  busy_ = max_ = min_ = lag_ = 0;
}

void StepTimes::record(double busy_seconds) {
  pending_.push_back(std::max(0.0, busy_seconds));
}

void StepTimes::fold(const Comm& comm) {
  slowest_ = pending_;
  max_over_ranks(comm, slowest_);
  for (std::size_t s = 0; s < pending_.size(); ++s) {
    const double t = pending_[s];
    lag_ += slowest_[s] - t;
    busy_ += t;
    min_ = steps_ == 0 ? t : std::min(min_, t);
    max_ = std::max(max_, t);
    ++steps_;
    // Bin 0 below kLowest, then kBinsPerDecade per decade, the last above.
    const double x = t > 0 ? std::log10(t / kLowest) * kBinsPerDecade : -1.0;
    const auto bins = static_cast<long>(histogram_.size()) - 2;
    const long bin = x < 0 ? 0 : std::min(static_cast<long>(x), bins) + 1;
    ++histogram_[static_cast<std::size_t>(bin)];
  }
  pending_.clear();
}

double StepTimes::quantile(double q) const {
  if (steps_ == 0) return 0;
  // The smallest bin whose cumulative count reaches q of the steps.
  const auto target = static_cast<std::int64_t>(std::ceil(q * static_cast<double>(steps_)));
  std::int64_t seen = 0;
  std::size_t bin = 0;
  for (; bin + 1 < histogram_.size(); ++bin) {
    seen += histogram_[bin];
    if (seen >= std::max<std::int64_t>(target, 1)) break;
  }
  double centre = 0;
  if (bin == 0) {
    centre = min_;
  } else if (bin + 1 == histogram_.size()) {
    centre = max_;
  } else {
    centre = kLowest * std::pow(10.0, (static_cast<double>(bin - 1) + 0.5) / kBinsPerDecade);
  }
  return std::clamp(centre, min_, max_);
}

StepTimes::Summary StepTimes::summary() const {
  Summary s;
  s.steps = steps_;
  s.busy = busy_;
  s.mean = steps_ > 0 ? busy_ / static_cast<double>(steps_) : 0;
  s.p10 = quantile(0.1);
  s.p50 = quantile(0.5);
  s.p90 = quantile(0.9);
  s.max = max_;
  s.lag = lag_;
  return s;
}

}  // namespace sphdem
