#include "sonarfusion/track_axis.hpp"

#include <cmath>

namespace sonarfusion {

void TrackAxis::add(double yaw) {
    if (!std::isfinite(yaw)) return;
    sum_cos2_ += std::cos(2.0 * yaw);
    sum_sin2_ += std::sin(2.0 * yaw);
    ++count_;
}

void TrackAxis::clear() {
    sum_cos2_ = sum_sin2_ = 0.0;
    count_ = 0;
}

Eigen::Vector2d TrackAxis::axis(double min_concentration) const {
    if (count_ == 0) return Eigen::Vector2d::Zero();
    const double resultant = std::hypot(sum_cos2_, sum_sin2_) / static_cast<double>(count_);
    if (!(resultant >= min_concentration) || resultant <= 0.0) return Eigen::Vector2d::Zero();
    const double heading = 0.5 * std::atan2(sum_sin2_, sum_cos2_);
    return Eigen::Vector2d(std::cos(heading), std::sin(heading));
}

void TrackAxis::saveState(StateWriter& w) const {
    w.pod(sum_cos2_);
    w.pod(sum_sin2_);
    w.pod(static_cast<int64_t>(count_));
}

bool TrackAxis::loadState(StateReader& r) {
    int64_t c = 0;
    if (!r.pod(sum_cos2_) || !r.pod(sum_sin2_) || !r.pod(c) || c < 0) return false;
    count_ = static_cast<long>(c);
    return true;
}

}  // namespace sonarfusion
