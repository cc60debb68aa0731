#include "mapper_config_yaml.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <stdexcept>

#include "sonarfusion/mapper.hpp"
#include "sonarfusion/variant.hpp"

namespace sonarfusion {

namespace {
using Setter = std::function<void(const YAML::Node&)>;

template <class T>
Setter set(T& field) {
    return [&field](const YAML::Node& n) { field = n.as<T>(); };
}
// Angles are written in degrees in the file and stored in radians.
Setter setDeg(double& field) {
    return [&field](const YAML::Node& n) { field = n.as<double>() * kDegToRad; };
}

void apply(const YAML::Node& node, const std::string& section, const std::map<std::string, Setter>& keys,
           const std::string& path) {
    if (!node) return;
    if (!node.IsMap()) throw std::runtime_error(path + ": '" + section + "' must be a mapping");
    for (const auto& kv : node) {
        const std::string key = kv.first.as<std::string>();
        auto it = keys.find(key);
        if (it == keys.end()) throw std::runtime_error(path + ": unknown key '" + section + "." + key + "'");
        try {
            it->second(kv.second);
        } catch (const YAML::Exception& e) {
            throw std::runtime_error(path + ": bad value for '" + section + "." + key + "': " + e.what());
        }
    }
}
}  // namespace

DaemonConfig loadDaemonConfig(const std::string& path) {
    YAML::Node root;
    try {
        root = YAML::LoadFile(path);
    } catch (const YAML::Exception& e) {
        throw std::runtime_error(path + ": " + e.what());
    }
    DaemonConfig d;
    MapperConfig& m = d.mapper;
    static const char* kSections[] = {"variant", "channels", "lcm_url", "daemon", "fls", "ps", "map", "update",
                                      "ps_selection", "detector", "segmentation", "nav"};
    for (const auto& kv : root) {
        const std::string key = kv.first.as<std::string>();
        bool known = false;
        for (const char* s : kSections) known |= key == s;
        if (!known) throw std::runtime_error(path + ": unknown key '" + key + "'");
    }
    if (root["variant"]) d.variant = root["variant"].as<std::string>();
    if (!parseVariant(d.variant)) throw std::runtime_error(path + ": variant must be fls_only, carve_only, paper or fused");
    applyVariant(*parseVariant(d.variant), m);  // presets first; explicit update keys below override
    if (root["lcm_url"]) d.lcm_url = root["lcm_url"].as<std::string>();
    apply(root["channels"], "channels",
          {{"nav", set(d.nav_channel)}, {"fls", set(d.fls_channel)}, {"ps", set(d.ps_channel)},
           {"status", set(d.status_channel)}, {"objects", set(d.objects_channel)}, {"map", set(d.map_channel)}},
          path);
    apply(root["daemon"], "daemon",
          {{"status_period_s", set(d.status_period_s)}, {"segment_period_s", set(d.segment_period_s)},
           {"map_period_s", set(d.map_period_s)}, {"budget_us", set(d.budget_us)},
           {"nav_wait_timeout_us", set(d.nav_wait_timeout_us)}, {"queue_capacity", set(d.queue_capacity)},
           {"fls_pending_slots", set(d.fls_pending_slots)}, {"ps_pending_slots", set(d.ps_pending_slots)},
           {"memory_budget_mb", set(d.memory_budget_mb)}, {"checkpoint_period_s", set(d.checkpoint_period_s)}},
          path);
    apply(root["fls"], "fls",
          {{"fov_horizontal_deg", setDeg(m.fls.fov_horizontal)}, {"elevation_min_deg", setDeg(m.fls.elevation_min)},
           {"elevation_max_deg", setDeg(m.fls.elevation_max)}, {"tilt_deg", setDeg(m.fls.tilt)},
           {"range_min", set(m.fls.range_min)}, {"range_max", set(m.fls.range_max)}, {"beams", set(m.fls.beams)},
           {"rows", set(m.fls.rows)}, {"elevation_samples", set(m.fls.elevation_samples)}},
          path);
    apply(root["ps"], "ps",
          {{"fan_min_deg", setDeg(m.ps.fan_min)}, {"fan_max_deg", setDeg(m.ps.fan_max)},
           {"head_min_deg", setDeg(m.ps.head_min)}, {"head_max_deg", setDeg(m.ps.head_max)},
           {"tilt_deg", setDeg(m.ps.tilt)}, {"range_min", set(m.ps.range_min)}, {"range_max", set(m.ps.range_max)},
           {"bins", set(m.ps.bins)}, {"fan_samples", set(m.ps.fan_samples)}},
          path);
    apply(root["map"], "map",
          {{"nx", set(m.map.nx)}, {"ny", set(m.map.ny)}, {"nz", set(m.map.nz)}, {"resolution", set(m.map.resolution)},
           {"clamp_min", set(m.map.clamp_min)}, {"clamp_max", set(m.map.clamp_max)},
           {"snap_to_world_lattice", set(m.map.snap_to_world_lattice)}},
          path);
    apply(root["update"], "update",
          {{"p_occupied", set(m.update.p_occupied)}, {"alpha_fls", set(m.update.alpha_fls)},
           {"p_free", set(m.update.p_free)}, {"alpha_ps", set(m.update.alpha_ps)},
           {"fls_intensity_threshold", set(m.update.fls_intensity_threshold)},
           {"fls_once_per_frame", set(m.update.fls_once_per_frame)},
           {"fls_arc_spacing_voxels", set(m.update.fls_arc_spacing_voxels)},
           {"fls_free_space", set(m.update.fls_free_space)},
           {"require_ps_observation", set(m.update.require_ps_observation)}},
          path);
    apply(root["ps_selection"], "ps_selection",
          {{"group_threshold", set(m.ps_selection.group_threshold)},
           {"normalise_by_ping_max", set(m.ps_selection.normalise_by_ping_max)},
           {"min_peak_intensity", set(m.ps_selection.min_peak_intensity)}, {"min_range", set(m.ps_selection.min_range)},
           {"weak_echoes_group", set(m.ps_selection.weak_echoes_group)}},
          path);
    apply(root["detector"], "detector",
          {{"seabed_radius", set(m.detector.seabed_radius)},
           {"seabed_capacity", set(m.detector.seabed_capacity)},
           {"min_seabed_echoes", set(m.detector.min_seabed_echoes)},
           {"min_rise", set(m.detector.min_rise)}, {"rise_sigmas", set(m.detector.rise_sigmas)},
           {"cluster_radius", set(m.detector.cluster_radius)},
           {"min_risen_echoes", set(m.detector.min_risen_echoes)},
           {"risen_capacity", set(m.detector.risen_capacity)}},
          path);
    apply(root["segmentation"], "segmentation",
          {{"occupied_probability", set(m.segmentation.occupied_probability)},
           {"baseline_window", set(m.segmentation.baseline_window)},
           {"min_object_height", set(m.segmentation.min_object_height)},
           {"min_object_voxels", set(m.segmentation.min_object_voxels)},
           {"max_objects", set(m.segmentation.max_objects)},
           {"baseline_along_track", set(m.segmentation.baseline_along_track)},
           {"seabed_from_ps_echoes", set(m.segmentation.seabed_from_ps_echoes)},
           {"ps_echo_min_fraction", set(m.segmentation.ps_echo_min_fraction)},
           {"fls_only_extension", set(m.segmentation.fls_only_extension)},
           {"fill_below_objects", set(m.segmentation.fill_below_objects)},
           {"low_layers_from_above", set(m.segmentation.low_layers_from_above)},
           {"ps_echo_radius", set(m.segmentation.ps_echo_radius)},
           {"ps_echo_min_count", set(m.segmentation.ps_echo_min_count)}},
          path);
    apply(root["nav"], "nav",
          {{"max_gap_us", set(m.max_nav_gap_us)}, {"buffer_capacity", set(m.nav_buffer_capacity)},
           {"timeline_confirm", set(m.nav_timeline_confirm)}},
          path);
    std::string err = validateConfig(m);
    if (err.empty()) err = validateDaemonConfig(d);
    if (!err.empty()) throw std::runtime_error(path + ": " + err);
    return d;
}

std::string validateDaemonConfig(const DaemonConfig& d) {
    // Periods are data seconds; a day is far beyond any sensible one, and the
    // microsecond conversion must not overflow (1e14 s published on every message).
    auto period = [](double p) { return std::isfinite(p) && p >= 0.0 && p <= 86400.0; };
    if (!period(d.status_period_s)) return "daemon.status_period_s must be in [0, 86400]";
    if (!period(d.segment_period_s)) return "daemon.segment_period_s must be in [0, 86400]";
    if (!std::isfinite(d.map_period_s) || d.map_period_s > 86400.0)
        return "daemon.map_period_s must be <= 86400 (<= 0: off)";
    if (!period(d.checkpoint_period_s)) return "daemon.checkpoint_period_s must be in [0, 86400]";
    if (!std::isfinite(d.budget_us) || d.budget_us <= 0.0) return "daemon.budget_us must be > 0";
    if (d.nav_wait_timeout_us < 1000 || d.nav_wait_timeout_us > 600000000)
        return "daemon.nav_wait_timeout_us must be in 1000..600000000";
    if (d.queue_capacity < 1 || d.queue_capacity > 100000) return "daemon.queue_capacity must be in 1..100000";
    if (d.fls_pending_slots < 2 || d.fls_pending_slots > 4096) return "daemon.fls_pending_slots must be in 2..4096";
    if (d.ps_pending_slots < 2 || d.ps_pending_slots > 65536) return "daemon.ps_pending_slots must be in 2..65536";
    if (!std::isfinite(d.memory_budget_mb) || d.memory_budget_mb <= 0.0)
        return "daemon.memory_budget_mb must be > 0";
    const std::pair<const char*, const std::string*> channels[] = {
        {"nav", &d.nav_channel},       {"fls", &d.fls_channel},         {"ps", &d.ps_channel},
        {"status", &d.status_channel}, {"objects", &d.objects_channel}, {"map", &d.map_channel}};
    for (const auto& [key, name] : channels) {
        // LCM channel names are at most 63 bytes.
        if (name->empty() || name->size() > 63) return std::string("channels.") + key + " must be 1..63 characters";
        for (const auto& [key2, name2] : channels)
            if (key != key2 && *name == *name2)
                return std::string("channels.") + key + " and channels." + key2 + " must differ";
    }
    const double need_mb = static_cast<double>(daemonMemoryBytes(d)) / (1024.0 * 1024.0);
    if (need_mb > d.memory_budget_mb)
        return "the map and buffers need about " + std::to_string(static_cast<long long>(need_mb)) +
               " MB, more than daemon.memory_budget_mb (" +
               std::to_string(static_cast<long long>(d.memory_budget_mb)) + "): reduce map.nx/ny/nz";
    return {};
}

std::size_t daemonMemoryBytes(const DaemonConfig& d) {
    const MapperConfig& m = d.mapper;
    const double voxels = static_cast<double>(m.map.nx) * m.map.ny * m.map.nz;
    const double fls_msg = static_cast<double>(m.fls.beams) * m.fls.rows + 8.0 * (m.fls.beams + m.fls.rows) + 512.0;
    const double ps_msg = static_cast<double>(m.ps.bins) + 512.0;
    const double bytes = static_cast<double>(estimatedMemoryBytes(m)) +
                         d.fls_pending_slots * fls_msg + d.ps_pending_slots * ps_msg +
                         voxels * 9.0 +  // MAP snapshot: index, log-odds, flags
                         voxels * 5.0 * 2.0 +  // checkpoint buffer (map copy), written from a second buffer
                         static_cast<double>(d.queue_capacity) * std::max(fls_msg, ps_msg);  // LCM's queue
    return bytes > 1e18 ? static_cast<std::size_t>(1e18) : static_cast<std::size_t>(bytes);
}

}  // namespace sonarfusion
