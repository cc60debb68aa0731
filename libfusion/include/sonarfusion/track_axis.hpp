// The vehicle's track axis, for the along-track seabed average of paper 2.4.
// Headings are averaged as axes (doubled angles), so the two straight passes of
// the reference survey, 0 and 180 degrees, share one axis.
#pragma once

#include <Eigen/Core>

#include "sonarfusion/state_codec.hpp"

namespace sonarfusion {

class TrackAxis {
public:
    // Vehicle yaw (rad, NED: 0 north, +pi/2 east). Non-finite values are ignored.
    void add(double yaw);
    void clear();
    void saveState(StateWriter& w) const;
    [[nodiscard]] bool loadState(StateReader& r);
    [[nodiscard]] long count() const { return count_; }
    // Unit (north, east) of the mean axis, or zero when there is no heading yet or
    // the headings do not agree on one axis: mean resultant length of the doubled
    // angles below min_concentration (1 = one axis, 0 = e.g. two crossing legs).
    [[nodiscard]] Eigen::Vector2d axis(double min_concentration = 0.5) const;

private:
    double sum_cos2_ = 0.0, sum_sin2_ = 0.0;
    long count_ = 0;
};

}  // namespace sonarfusion
