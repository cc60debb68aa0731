// Mapper configuration from YAML (docs/mapper-config.md). Unknown keys are an
// error naming the key, so a typo never silently falls back to a default.
#pragma once

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
    int64_t nav_wait_timeout_us = 500000;  // sonar waits at most this long for a later NAV
    int queue_capacity = 2000;        // LCM subscription queue (default 30 drops bursts)
};

// Throws std::runtime_error naming the file and the offending key.
DaemonConfig loadDaemonConfig(const std::string& path);

}  // namespace sonarfusion
