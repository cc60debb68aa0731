// Mapper configuration from YAML (docs/mapper-config.md), part of the shared
// config reader (sf_config_yaml; its sensor blocks are read as the scenario's
// are, config_yaml.hpp). Unknown keys are an error naming the key, so a typo
// never silently falls back to a default.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include "sonarfusion/config.hpp"

namespace sonarfusion {

struct DaemonConfig {
    MapperConfig mapper;
    std::string variant = "fused";
    std::string nav_channel = "NAV", fls_channel = "FLS", ps_channel = "PS";
    std::string status_channel = "MAPPER_STATUS", objects_channel = "OBJECTS", map_channel = "MAP";
    std::string lcm_url = "udpm://239.255.76.67:7667?ttl=0";
    double status_period_s = 1.0;     // MAPPER_STATUS rate
    double segment_period_s = 2.0;    // OBJECTS: segmentation every this many seconds of data
    double map_period_s = 5.0;        // MAP snapshots; <= 0 disables
    double budget_us = 20000.0;       // per-message processing budget for overrun counting
    int64_t nav_wait_timeout_us = 5000000;  // live: sonar waits at most this long for a later NAV
    int queue_capacity = 2000;        // LCM subscription queue (default 30 drops bursts)
    // Sonar messages waiting for NAV, decoded in place. When all are taken the
    // waiting set is thinned (the message whose removal leaves the smallest
    // time gap goes), so late NAV degrades the map gradually (issue 10, finding 6).
    int fls_pending_slots = 16;
    int ps_pending_slots = 64;
    double memory_budget_mb = 2048.0;  // refuse at start-up a config that would need more
    double checkpoint_period_s = 10.0; // with --checkpoint: data seconds between checkpoints (0: only at exit)
    // mapper.validate(), then the daemon's own keys ("daemon.queue_capacity",
    // "channels.fls") and the memory budget (config.hpp's ConfigIssue).
    [[nodiscard]] std::optional<ConfigIssue> validate() const;
};

// d.validate() as one message naming the key ("channels.fls: must differ from
// channels.nav"); "" when fine.
[[nodiscard]] std::string validateDaemonConfig(const DaemonConfig& d);
// Bytes the daemon allocates at start-up for this config (libfusion's estimate,
// the pending slots, the MAP snapshot and the checkpoint buffer).
[[nodiscard]] std::size_t daemonMemoryBytes(const DaemonConfig& d);

// Throws std::runtime_error naming the file and the offending key: "FILE: map.nx:
// must be in 1..4096" (a value), "FILE: fls.range_maxx: unknown key".
DaemonConfig loadDaemonConfig(const std::string& path);

}  // namespace sonarfusion
