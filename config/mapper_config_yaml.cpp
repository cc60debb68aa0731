#include "mapper_config_yaml.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <stdexcept>

#include "config_yaml.hpp"
#include "sonarfusion/mapper.hpp"
#include "sonarfusion/variant.hpp"

namespace sonarfusion {

namespace {

using config_yaml::Fields;
using config_yaml::KeyError;

DaemonConfig parse(const YAML::Node& root) {
    DaemonConfig d;
    MapperConfig& m = d.mapper;
    Fields top(root, "");
    // The variant's update preset first; explicit update keys below override it.
    top.read("variant", d.variant);
    const auto variant = parseVariant(d.variant);
    if (!variant) throw KeyError("variant", "must be fls_only, carve_only, paper or fused");
    applyVariant(*variant, m);
    top.read("lcm_url", d.lcm_url);

    Fields ch(top.child("channels"), "channels");
    ch.read("nav", d.nav_channel);
    ch.read("fls", d.fls_channel);
    ch.read("ps", d.ps_channel);
    ch.read("status", d.status_channel);
    ch.read("objects", d.objects_channel);
    ch.read("map", d.map_channel);
    ch.rejectUnknownKeys();

    Fields dm(top.child("daemon"), "daemon");
    dm.read("status_period_s", d.status_period_s);
    dm.read("segment_period_s", d.segment_period_s);
    dm.read("map_period_s", d.map_period_s);
    dm.read("budget_us", d.budget_us);
    dm.read("nav_wait_timeout_us", d.nav_wait_timeout_us);
    dm.read("queue_capacity", d.queue_capacity);
    dm.read("fls_pending_slots", d.fls_pending_slots);
    dm.read("ps_pending_slots", d.ps_pending_slots);
    dm.read("memory_budget_mb", d.memory_budget_mb);
    dm.read("checkpoint_period_s", d.checkpoint_period_s);
    dm.rejectUnknownKeys();

    // The sensor blocks, read as the scenario reads them (config_yaml.hpp).
    Fields fls(top.child("fls"), "fls");
    config_yaml::readFlsGeometry(fls, m.fls);
    config_yaml::readMounting(fls.child("mount"), "fls.mount", m.fls_mount);
    fls.read("max_geometries", m.fls_max_geometries);  // the mapper's, not the sonar's (not in a scenario)
    fls.rejectUnknownKeys();
    Fields ps(top.child("ps"), "ps");
    config_yaml::readPsGeometry(ps, m.ps);
    ps.readDegrees("beam_width_vertical_deg", m.ps.beam_width_vertical);  // the mapper's only
    config_yaml::readMounting(ps.child("mount"), "ps.mount", m.ps_mount);
    ps.rejectUnknownKeys();

    Fields map(top.child("map"), "map");
    map.read("nx", m.map.nx);
    map.read("ny", m.map.ny);
    map.read("nz", m.map.nz);
    map.read("resolution", m.map.resolution);
    map.read("clamp_min", m.map.clamp_min);
    map.read("clamp_max", m.map.clamp_max);
    map.read("snap_to_world_lattice", m.map.snap_to_world_lattice);
    map.rejectUnknownKeys();

    Fields up(top.child("update"), "update");
    up.read("p_occupied", m.update.p_occupied);
    up.read("alpha_fls", m.update.alpha_fls);
    up.read("p_free", m.update.p_free);
    up.read("alpha_ps", m.update.alpha_ps);
    up.read("fls_intensity_threshold", m.update.fls_intensity_threshold);
    up.read("fls_once_per_frame", m.update.fls_once_per_frame);
    up.read("fls_arc_spacing_voxels", m.update.fls_arc_spacing_voxels);
    up.read("fls_free_space", m.update.fls_free_space);
    up.read("fls_free_space_noise_sigmas", m.update.fls_free_space_noise_sigmas);
    up.read("ps_carve_noise_sigmas", m.update.ps_carve_noise_sigmas);
    up.read("ps_carve_echo_window_voxels", m.update.ps_carve_echo_window_voxels);
    up.read("ps_carve_spare_echo_share", m.update.ps_carve_spare_echo_share);
    up.read("ps_carve_spare_min_echoes", m.update.ps_carve_spare_min_echoes);
    up.read("fls_free_vote_ratio", m.update.fls_free_vote_ratio);
    up.read("fls_highlight_above_seabed", m.update.fls_highlight_above_seabed);
    up.read("fls_highlight_half_window", m.update.fls_highlight_half_window);
    up.read("fls_highlight_false_alarm", m.update.fls_highlight_false_alarm);
    up.read("fls_seabed_at_footprint", m.update.fls_seabed_at_footprint);
    up.read("fls_seabed_judged_later", m.update.fls_seabed_judged_later);
    up.read("require_ps_observation", m.update.require_ps_observation);
    up.rejectUnknownKeys();

    Fields sel(top.child("ps_selection"), "ps_selection");
    sel.read("group_threshold", m.ps_selection.group_threshold);
    sel.read("normalise_by_ping_max", m.ps_selection.normalise_by_ping_max);
    sel.read("min_peak_intensity", m.ps_selection.min_peak_intensity);
    sel.read("min_range", m.ps_selection.min_range);
    sel.read("weak_echoes_group", m.ps_selection.weak_echoes_group);
    sel.rejectUnknownKeys();

    Fields det(top.child("detector"), "detector");
    det.read("seabed_radius", m.detector.seabed_radius);
    det.read("seabed_capacity", m.detector.seabed_capacity);
    det.read("min_seabed_echoes", m.detector.min_seabed_echoes);
    det.read("min_rise", m.detector.min_rise);
    det.read("rise_sigmas", m.detector.rise_sigmas);
    det.read("rise_from_deepest_in_beam", m.detector.rise_from_deepest_in_beam);
    det.read("cluster_radius", m.detector.cluster_radius);
    det.read("min_risen_echoes", m.detector.min_risen_echoes);
    det.read("risen_capacity", m.detector.risen_capacity);
    det.read("rise_from_lower_envelope", m.detector.rise_from_lower_envelope);
    det.read("rise_trim_converges", m.detector.rise_trim_converges);
    det.read("judge_early_echoes", m.detector.judge_early_echoes);
    det.read("judge_early_echoes_by_tighter_plane", m.detector.judge_early_echoes_by_tighter_plane);
    det.read("seabed_across_lines", m.detector.seabed_across_lines);
    det.read("envelope_per_line", m.detector.envelope_per_line);
    det.read("nearest_echo_sigmas", m.detector.nearest_echo_sigmas);
    det.read("fls_nearer_than_seabed", m.detector.fls_nearer_than_seabed);
    det.read("fls_shadow_false_alarm", m.detector.fls_shadow_false_alarm);
    det.read("fls_shadow_min_frames", m.detector.fls_shadow_min_frames);
    det.read("fls_shadow_like_water", m.detector.fls_shadow_like_water);
    det.read("replay_pings", m.detector.replay_pings);
    det.read("replay_pings_carve_only", m.detector.replay_pings_carve_only);
    det.read("replay_risen_pings_whole", m.detector.replay_risen_pings_whole);
    det.read("replay_fls_frames", m.detector.replay_fls_frames);
    det.rejectUnknownKeys();

    Fields seg(top.child("segmentation"), "segmentation");
    SegmentationConfig& g = m.segmentation;
    seg.read("occupied_probability", g.occupied_probability);
    seg.read("baseline_window", g.baseline_window);
    seg.read("min_object_height", g.min_object_height);
    seg.read("min_object_voxels", g.min_object_voxels);
    seg.read("max_objects", g.max_objects);
    seg.read("baseline_along_track", g.baseline_along_track);
    seg.read("seabed_from_ps_echoes", g.seabed_from_ps_echoes);
    seg.read("ps_echo_min_fraction", g.ps_echo_min_fraction);
    seg.read("ps_echo_reference_above_seabed", g.ps_echo_reference_above_seabed);
    seg.read("ps_echo_seen_above_seabed", g.ps_echo_seen_above_seabed);
    seg.read("ps_crossed_confirmed_from_level_or_above", g.ps_crossed_confirmed_from_level_or_above);
    seg.read("fls_only_extension", g.fls_only_extension);
    if (seg.has("fls_above_seabed_min_votes")) seg.read("fls_above_seabed_min_votes", g.fls_above_seabed_min_votes);
    else {  // derived from the update model (docs/mapper-config.md): 1..255 (the count saturates there)
        const double votes = std::ceil(logOddsFromProbability(g.occupied_probability) /
                                           (m.update.alpha_fls * logOddsFromProbability(m.update.p_occupied)) - 1e-9);
        g.fls_above_seabed_min_votes = votes >= 1.0 ? static_cast<int>(std::min(votes, 255.0)) : 1;  // NaN: 1
    }
    seg.read("fls_only_needs_support", g.fls_only_needs_support);
    seg.read("fls_only_not_above_ps_top", g.fls_only_not_above_ps_top);
    seg.read("low_echoes_seen_above_seabed", g.low_echoes_seen_above_seabed);
    if (seg.has("fls_votes_per_ps_crossing")) seg.read("fls_votes_per_ps_crossing", g.fls_votes_per_ps_crossing);
    else {  // derived from the update model (docs/mapper-config.md): the crossing's weakest carve over a full vote
        const double per = -logOddsFromProbability(m.update.p_free) * std::exp(-m.update.alpha_ps) /
                           (m.update.alpha_fls * logOddsFromProbability(m.update.p_occupied));
        g.fls_votes_per_ps_crossing = std::isfinite(per) && per > 0.0 ? per : 0.0;  // votes that add nothing: off
    }
    seg.read("base_follows_sloped_faces", g.base_follows_sloped_faces);
    seg.read("join_touching_floods", g.join_touching_floods);
    seg.read("fill_below_objects", g.fill_below_objects);
    seg.read("fill_below_not_through_crossed_water", g.fill_below_not_through_crossed_water);
    seg.read("fill_below_through_unobserved", g.fill_below_through_unobserved);
    seg.read("fill_below_widens_through_unobserved", g.fill_below_widens_through_unobserved);
    seg.read("seabed_from_lower_envelope", g.seabed_from_lower_envelope);
    seg.read("seabed_at_echo_centres", g.seabed_at_echo_centres);
    seg.read("seabed_raised_sigmas", g.seabed_raised_sigmas);
    seg.read("low_layers_from_above", g.low_layers_from_above);
    seg.read("low_layers_widen_where_seen", g.low_layers_widen_where_seen);
    seg.read("ps_echo_radius", g.ps_echo_radius);
    seg.read("ps_echo_min_count", g.ps_echo_min_count);
    seg.rejectUnknownKeys();

    Fields survey(top.child("survey"), "survey");
    survey.read("max_maps", m.survey.max_maps);
    survey.read("release_margin", m.survey.release_margin);
    survey.read("published_capacity", m.survey.published_capacity);
    survey.read("reopen_on_revisit", m.survey.reopen_on_revisit);
    survey.rejectUnknownKeys();

    Fields nav(top.child("nav"), "nav");
    nav.read("max_gap_us", m.max_nav_gap_us);
    nav.read("buffer_capacity", m.nav_buffer_capacity);
    nav.read("timeline_confirm", m.nav_timeline_confirm);
    nav.rejectUnknownKeys();

    top.rejectUnknownKeys();
    config_yaml::requireValid(d, "");
    return d;
}

}  // namespace

DaemonConfig loadDaemonConfig(const std::string& path) {
    YAML::Node root;
    try {
        root = YAML::LoadFile(path);
    } catch (const YAML::Exception& e) {
        throw std::runtime_error(path + ": " + e.what());
    }
    if (root && !root.IsNull() && !root.IsMap()) throw std::runtime_error(path + ": the top level must be a mapping");
    try {
        return parse(root);
    } catch (const KeyError& e) {
        throw std::runtime_error(path + ": " + e.what());
    }
}

std::optional<ConfigIssue> DaemonConfig::validate() const {
    if (auto issue = mapper.validate()) return issue;
    auto bad = [](const std::string& key, const std::string& reason) { return ConfigIssue{key, reason}; };
    // Periods are data seconds; a day is far beyond any sensible one, and the
    // microsecond conversion must not overflow (1e14 s published on every message).
    auto period = [](double p) { return std::isfinite(p) && p >= 0.0 && p <= 86400.0; };
    if (!period(status_period_s)) return bad("daemon.status_period_s", "must be in [0, 86400]");
    if (!period(segment_period_s)) return bad("daemon.segment_period_s", "must be in [0, 86400]");
    if (!std::isfinite(map_period_s) || map_period_s > 86400.0)
        return bad("daemon.map_period_s", "must be <= 86400 (<= 0: off)");
    if (!period(checkpoint_period_s)) return bad("daemon.checkpoint_period_s", "must be in [0, 86400]");
    if (!std::isfinite(budget_us) || budget_us <= 0.0) return bad("daemon.budget_us", "must be > 0");
    if (nav_wait_timeout_us < 1000 || nav_wait_timeout_us > 600000000)
        return bad("daemon.nav_wait_timeout_us", "must be in 1000..600000000");
    if (queue_capacity < 1 || queue_capacity > 100000) return bad("daemon.queue_capacity", "must be in 1..100000");
    if (fls_pending_slots < 2 || fls_pending_slots > 4096) return bad("daemon.fls_pending_slots", "must be in 2..4096");
    if (ps_pending_slots < 2 || ps_pending_slots > 65536) return bad("daemon.ps_pending_slots", "must be in 2..65536");
    if (!std::isfinite(memory_budget_mb) || memory_budget_mb <= 0.0)
        return bad("daemon.memory_budget_mb", "must be > 0");
    const std::pair<const char*, const std::string*> channels[] = {
        {"nav", &nav_channel},       {"fls", &fls_channel},         {"ps", &ps_channel},
        {"status", &status_channel}, {"objects", &objects_channel}, {"map", &map_channel}};
    for (std::size_t i = 0; i < std::size(channels); ++i) {
        const auto& [key, name] = channels[i];
        // LCM channel names are at most 63 bytes.
        if (name->empty() || name->size() > 63) return bad(std::string("channels.") + key, "must be 1..63 characters");
        for (std::size_t j = 0; j < i; ++j)
            if (*name == *channels[j].second)
                return bad(std::string("channels.") + key,
                           std::string("must differ from channels.") + channels[j].first);
    }
    const double need_mb = static_cast<double>(daemonMemoryBytes(*this)) / (1024.0 * 1024.0);
    if (need_mb > memory_budget_mb)
        return bad("daemon.memory_budget_mb", "is " + std::to_string(static_cast<long long>(memory_budget_mb)) +
                                                  " MB, and the map and buffers need about " +
                                                  std::to_string(static_cast<long long>(need_mb)) +
                                                  " MB: reduce map.nx/ny/nz");
    return std::nullopt;
}

std::string validateDaemonConfig(const DaemonConfig& d) {
    const std::optional<ConfigIssue> issue = d.validate();
    return issue ? issue->message() : std::string();
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
