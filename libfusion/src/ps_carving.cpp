#include "sonarfusion/ps_carving.hpp"

#include <algorithm>
#include <cmath>


namespace sonarfusion {

PsCarver::PsCarver(const PsModel& model, const UpdateConfig& cfg)
    : model_(model), cfg_(cfg),
      free_increment_(static_cast<float>(logOddsFromProbability(cfg.p_free))),
      hit_increment_(static_cast<float>(logOddsFromProbability(cfg.p_occupied))) {}

double carveStopRange(const PsPing& ping, const PsEchoGroup& group, const PsSelectionConfig& selection,
                      double noise_sigmas, double echo_window) {
    if (!(noise_sigmas > 0.0)) return -1.0;
    int stop = group.first;
    int window_bins = 0;
    if (echo_window > 0.0 && ping.bins > 1) {
        const double bin = rangeOfBin(ping, 1) - rangeOfBin(ping, 0);
        // Bins at most the ping long (a window longer than the ping finds nothing).
        if (bin > 0.0)
            window_bins = static_cast<int>(std::clamp(std::round(echo_window / bin), 2.0, static_cast<double>(ping.bins)));
    }
    const int echo = firstEchoBin(ping, selection, noise_sigmas, window_bins);
    if (echo >= 0) stop = std::min(stop, echo);
    return stop >= group.peak ? -1.0 : rangeOfBin(ping, stop);
}

PsCarveStats PsCarver::apply(double head_angle, double selected_range, const Eigen::Isometry3d& world_from_sensor,
                             VoxelMap& map, double echo_strength, double carve_range) const {
    MapWriterSink sink(map);
    return apply(head_angle, selected_range, world_from_sensor, map, sink, echo_strength, carve_range);
}

}  // namespace sonarfusion
