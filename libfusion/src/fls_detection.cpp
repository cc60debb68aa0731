#include "sonarfusion/fls_detection.hpp"

#include <algorithm>
#include <limits>

namespace sonarfusion {

std::optional<Eigen::Vector3d> flsReturnNearerThanSeabed(const FlsFrame& frame, const FlsModel& model,
                                                         const Eigen::Isometry3d& world_from_sensor,
                                                         const SeabedFit& seabed, int vote_threshold, double margin) {
    const Eigen::Vector3d sensor = world_from_sensor.translation();
    const double depth_below = seabed.depthAt(sensor.head<2>()) - sensor.z() - margin;
    if (!(depth_below > 0.0)) return std::nullopt;
    const double lo = model.elevationMin(), hi = model.elevationMax(), mid = 0.5 * (lo + hi);
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    int n = 0;
    for (int col = 0; col < frame.cols; ++col) {
        // A ray meets the raised plane at depth_below / closing rate; the arc's
        // nearest such range is on one of its edges (the rate is monotonic in
        // elevation) or, with roll, near its centre.
        double nearest = std::numeric_limits<double>::infinity();
        for (double e : {lo, mid, hi}) {
            const double rate = seabed.closingRate(world_from_sensor.linear() * model.directionAt(col, e).cast<double>());
            if (rate > 1e-6) nearest = std::min(nearest, depth_below / rate);
        }
        const Eigen::Vector3d centre = world_from_sensor.linear() * model.directionAt(col, mid).cast<double>();
        // Rows run from the far end: walk in from the nearest row while it is nearer than the seabed.
        for (int row = frame.rows - 1; row >= 0; --row) {
            const double r = model.rangeOfRow(row);
            if (!(r < nearest)) break;
            if (frame.data[static_cast<std::size_t>(row) * frame.cols + col] <= vote_threshold) continue;
            sum += sensor + r * centre;
            ++n;
        }
    }
    if (n == 0) return std::nullopt;
    return sum / n;
}

}  // namespace sonarfusion
