// validate() of every config struct (config.hpp): each value something is
// allocated from, divided by or compared with, checked once, here. The
// constructors that take these structs (FlsModel, PsModel, VoxelMap,
// ObjectDetector, Segmenter, NavBuffer) refuse nothing these accept.
#include "sonarfusion/config.hpp"
#include "sonarfusion/voxel_map.hpp"

#include <cmath>
#include <string>

namespace sonarfusion {

namespace {

using Check = std::optional<ConfigIssue>;

Check bad(const char* key, const std::string& reason) { return ConfigIssue{key, reason}; }
bool finite(double v) { return std::isfinite(v); }
// An angle in radians, written in degrees in the files: finite, |a| <= 180 deg.
bool angle(double a) { return finite(a) && std::fabs(a) <= M_PI; }
bool inRange(long long v, long long lo, long long hi) { return v >= lo && v <= hi; }
std::string range(long long lo, long long hi) { return "must be in " + std::to_string(lo) + ".." + std::to_string(hi); }

// The first issue of a list of blocks, each named as in the files.
template <class... Blocks>
Check first(const std::pair<const char*, Check>& head, const Blocks&... rest) {
    if (head.second) return head.second->in(head.first);
    if constexpr (sizeof...(rest) > 0) return first(rest...);
    return std::nullopt;
}

}  // namespace

Check FlsGeometry::validate() const {
    if (!angle(fov_horizontal) || fov_horizontal <= 0.0) return bad("fov_horizontal_deg", "must be in (0, 180]");
    if (!angle(elevation_min)) return bad("elevation_min_deg", "must be finite, in [-180, 180]");
    if (!angle(elevation_max) || elevation_max <= elevation_min)
        return bad("elevation_max_deg", "must be finite, in [-180, 180] and above elevation_min_deg");
    if (!angle(tilt)) return bad("tilt_deg", "must be finite, in [-180, 180]");
    if (!finite(range_min) || range_min < 0.0) return bad("range_min", "must be finite and >= 0");
    if (!finite(range_max) || range_max <= range_min || range_max > 1000.0)
        return bad("range_max", "must be above range_min and <= 1000 m");
    if (!inRange(beams, 1, kMaxFlsBeams)) return bad("beams", range(1, kMaxFlsBeams));
    if (!inRange(rows, 2, kMaxFlsRows)) return bad("rows", range(2, kMaxFlsRows));
    if (!inRange(elevation_samples, 1, 256)) return bad("elevation_samples", range(1, 256));
    if (!beam_bearing.empty()) {
        if (beam_bearing.size() != static_cast<std::size_t>(beams))
            return bad("beam_bearing_deg", "must have one entry per beam (" + std::to_string(beams) + ")");
        for (double b : beam_bearing)
            if (!angle(b)) return bad("beam_bearing_deg", "every entry must be finite, in [-180, 180]");
    }
    if (!row_range.empty()) {
        if (row_range.size() != static_cast<std::size_t>(rows))
            return bad("row_range", "must have one entry per row (" + std::to_string(rows) + ")");
        for (double r : row_range)
            if (!finite(r) || r < 0.0 || r > 1000.0) return bad("row_range", "every entry must be in [0, 1000] m");
    }
    return std::nullopt;
}

Check PsGeometry::validate() const {
    if (!angle(fan_min)) return bad("fan_min_deg", "must be finite, in [-180, 180]");
    if (!angle(fan_max) || fan_max <= fan_min)
        return bad("fan_max_deg", "must be finite, in [-180, 180] and above fan_min_deg");
    if (!angle(head_min)) return bad("head_min_deg", "must be finite, in [-180, 180]");
    if (!angle(head_max) || head_max < head_min)
        return bad("head_max_deg", "must be finite, in [-180, 180] and not below head_min_deg");
    if (!angle(tilt)) return bad("tilt_deg", "must be finite, in [-180, 180]");
    if (!finite(range_min) || range_min < 0.0) return bad("range_min", "must be finite and >= 0");
    if (!finite(range_max) || range_max <= range_min || range_max > 1000.0)
        return bad("range_max", "must be above range_min and <= 1000 m");
    if (!inRange(bins, 2, kMaxPsBins)) return bad("bins", range(2, kMaxPsBins));
    if (!inRange(fan_samples, 1, 1024)) return bad("fan_samples", range(1, 1024));
    if (!finite(beam_width_vertical) || beam_width_vertical < 0.0 || beam_width_vertical > 30.0 * kDegToRad)
        return bad("beam_width_vertical_deg", "must be finite, in [0, 30]");
    return std::nullopt;
}

Check Mounting::validate() const {
    if (!finite(x)) return bad("x", "must be finite");
    if (!finite(y)) return bad("y", "must be finite");
    if (!finite(z)) return bad("z", "must be finite");
    if (!angle(roll)) return bad("roll_deg", "must be finite, in [-180, 180]");
    if (!angle(yaw)) return bad("yaw_deg", "must be finite, in [-180, 180]");
    return std::nullopt;
}

Check MapConfig::validate() const {
    if (!inRange(nx, 1, kMaxMapCells)) return bad("nx", range(1, kMaxMapCells));
    if (!inRange(ny, 1, kMaxMapCells)) return bad("ny", range(1, kMaxMapCells));
    if (!inRange(nz, 1, kMaxMapCells)) return bad("nz", range(1, kMaxMapCells));
    if (!finite(resolution) || resolution <= 0.0) return bad("resolution", "must be a positive number");
    if (!std::isfinite(clamp_min) || !(clamp_min < 0.0f)) return bad("clamp_min", "must be finite and < 0");
    if (!std::isfinite(clamp_max) || !(clamp_max > 0.0f)) return bad("clamp_max", "must be finite and > 0");
    return std::nullopt;
}

Check UpdateConfig::validate() const {
    if (!(p_occupied > 0.5 && p_occupied < 1.0)) return bad("p_occupied", "must be in (0.5, 1)");
    if (!(alpha_fls > 0.0) || !finite(alpha_fls)) return bad("alpha_fls", "must be finite and > 0");
    if (!(fls_free_vote_ratio > 0.0) || !finite(fls_free_vote_ratio)) return bad("fls_free_vote_ratio", "must be finite and > 0");
    if (!(p_free > 0.0 && p_free < 0.5)) return bad("p_free", "must be in (0, 0.5)");
    if (!inRange(fls_highlight_half_window, 0, 8)) return bad("fls_highlight_half_window", range(0, 8));
    if (!(fls_highlight_false_alarm > 0.0 && fls_highlight_false_alarm < 1.0))
        return bad("fls_highlight_false_alarm", "must be in (0, 1)");
    if (!(alpha_ps >= 0.0) || !finite(alpha_ps)) return bad("alpha_ps", "must be finite and >= 0");
    if (!inRange(fls_intensity_threshold, 0, 255)) return bad("fls_intensity_threshold", range(0, 255));
    if (!(fls_free_space_noise_sigmas >= 0.0) || !finite(fls_free_space_noise_sigmas))
        return bad("fls_free_space_noise_sigmas", "must be finite and >= 0 (0: free space up to the first vote)");
    if (!(ps_carve_noise_sigmas >= 0.0) || !finite(ps_carve_noise_sigmas))
        return bad("ps_carve_noise_sigmas", "must be finite and >= 0 (0: carve up to the selected echo)");
    if (!(ps_carve_echo_window_voxels >= 0.0 && ps_carve_echo_window_voxels <= 100.0))
        return bad("ps_carve_echo_window_voxels", "must be in [0, 100] (0: no window)");
    if (!(ps_carve_spare_echo_share >= 0.0 && ps_carve_spare_echo_share <= 1.0))
        return bad("ps_carve_spare_echo_share", "must be in [0, 1] (0: every crossed voxel is carved)");
    if (!inRange(ps_carve_spare_min_echoes, 1, VoxelMap::kPsEchoMax))
        return bad("ps_carve_spare_min_echoes", range(1, VoxelMap::kPsEchoMax));
    // The arc sample tables are sized from it.
    if (!(fls_arc_spacing_voxels == 0.0 || (fls_arc_spacing_voxels >= 0.25 && fls_arc_spacing_voxels <= 100.0)))
        return bad("fls_arc_spacing_voxels", "must be 0 (N_v samples) or in [0.25, 100]");
    return std::nullopt;
}

Check PsSelectionConfig::validate() const {
    if (!(group_threshold >= 0.0 && group_threshold < 1.0)) return bad("group_threshold", "must be in [0, 1)");
    if (!inRange(min_peak_intensity, 0, 255)) return bad("min_peak_intensity", range(0, 255));
    if (!(min_range >= 0.0) || !finite(min_range)) return bad("min_range", "must be finite and >= 0");
    return std::nullopt;
}

Check DetectorConfig::validate() const {
    if (!(seabed_radius > 0.0) || !finite(seabed_radius)) return bad("seabed_radius", "must be finite and > 0");
    if (!inRange(seabed_capacity, 3, 1000000)) return bad("seabed_capacity", range(3, 1000000));
    if (!inRange(min_seabed_echoes, 3, seabed_capacity))
        return bad("min_seabed_echoes", "must be in 3..seabed_capacity (" + std::to_string(seabed_capacity) + ")");
    if (!(min_rise > 0.0) || !finite(min_rise)) return bad("min_rise", "must be finite and > 0");
    if (!(rise_sigmas >= 0.0) || !finite(rise_sigmas)) return bad("rise_sigmas", "must be finite and >= 0");
    if (!(cluster_radius > 0.0) || !finite(cluster_radius)) return bad("cluster_radius", "must be finite and > 0");
    if (!inRange(risen_capacity, 1, 65536)) return bad("risen_capacity", range(1, 65536));
    if (!inRange(min_risen_echoes, 1, risen_capacity))
        return bad("min_risen_echoes", "must be in 1..risen_capacity (" + std::to_string(risen_capacity) + ")");
    if (!inRange(replay_pings, 0, 65536)) return bad("replay_pings", range(0, 65536));
    if (!inRange(replay_fls_frames, 0, 4096)) return bad("replay_fls_frames", range(0, 4096));
    if (!(nearest_echo_sigmas >= 0.0 && nearest_echo_sigmas <= 100.0))
        return bad("nearest_echo_sigmas", "must be in [0, 100] (0: the strongest bin only)");
    if (!(fls_shadow_false_alarm >= 0.0 && fls_shadow_false_alarm <= 1.0))
        return bad("fls_shadow_false_alarm", "must be in [0, 1] (expected runs per frame; 0: no shadow evidence)");
    if (!inRange(fls_shadow_min_frames, 1, risen_capacity))
        return bad("fls_shadow_min_frames", "must be in 1..risen_capacity (" + std::to_string(risen_capacity) +
                                                "; the shadows' ring holds as many)");
    return std::nullopt;
}

Check SegmentationConfig::validate() const {
    if (!(occupied_probability > 0.0 && occupied_probability < 1.0))
        return bad("occupied_probability", "must be in (0, 1)");
    if (!(baseline_window > 0.0) || !finite(baseline_window)) return bad("baseline_window", "must be finite and > 0");
    if (!(min_object_height >= 0.0) || !finite(min_object_height))
        return bad("min_object_height", "must be finite and >= 0");
    if (!(seabed_raised_sigmas >= 0.0) || !finite(seabed_raised_sigmas))
        return bad("seabed_raised_sigmas", "must be finite and >= 0 (0: min_object_height only)");
    if (min_object_voxels < 1) return bad("min_object_voxels", "must be >= 1");
    if (!inRange(max_objects, 1, 65535)) return bad("max_objects", range(1, 65535));
    if (!inRange(fls_only_extension, 0, 255)) return bad("fls_only_extension", range(0, 255));  // steps in a byte
    if (!inRange(fls_above_seabed_min_votes, 0, 255))  // the per-voxel count saturates at 255
        return bad("fls_above_seabed_min_votes", range(0, 255));
    if (!(fls_votes_per_ps_crossing >= 0.0) || !finite(fls_votes_per_ps_crossing))
        return bad("fls_votes_per_ps_crossing", "must be finite and >= 0 (0: off)");
    if (ps_echo_min_count < 1) return bad("ps_echo_min_count", "must be >= 1");
    if (!(ps_echo_min_fraction >= 0.0 && ps_echo_min_fraction <= 1.0))
        return bad("ps_echo_min_fraction", "must be in [0, 1]");
    return std::nullopt;
}

Check SurveyConfig::validate() const {
    if (!inRange(max_maps, 1, kMaxSurveyMaps)) return bad("max_maps", range(1, kMaxSurveyMaps));
    if (!finite(release_margin) || release_margin > 10000.0)
        return bad("release_margin", "must be finite and <= 10000 m (negative: the sonars' maximum range)");
    if (!inRange(published_capacity, 1, 1000000)) return bad("published_capacity", range(1, 1000000));
    return std::nullopt;
}

Check MapperConfig::validate() const {
    if (Check c = first(std::pair{"fls", fls.validate()}, std::pair{"fls.mount", fls_mount.validate()},
                        std::pair{"ps", ps.validate()}, std::pair{"ps.mount", ps_mount.validate()},
                        std::pair{"map", map.validate()}, std::pair{"update", update.validate()},
                        std::pair{"ps_selection", ps_selection.validate()}, std::pair{"detector", detector.validate()},
                        std::pair{"segmentation", segmentation.validate()}, std::pair{"survey", survey.validate()}))
        return c;
    if (!inRange(fls_max_geometries, 1, kMaxFlsGeometries)) return bad("fls.max_geometries", range(1, kMaxFlsGeometries));
    if (max_nav_gap_us <= 0) return bad("nav.max_gap_us", "must be > 0");
    if (!inRange(nav_buffer_capacity, 2, 1000000)) return bad("nav.buffer_capacity", range(2, 1000000));
    if (!inRange(nav_timeline_confirm, 1, kMaxNavTimelineConfirm))
        return bad("nav.timeline_confirm", range(1, kMaxNavTimelineConfirm));
    return std::nullopt;
}

}  // namespace sonarfusion
