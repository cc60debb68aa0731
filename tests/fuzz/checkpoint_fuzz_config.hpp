// The small daemon config the checkpoint fuzzer and its seed corpus share: an
// 8^3 map and small rings keep a valid state a few kB.
#pragma once

#include "mapper_config_yaml.hpp"

namespace sffuzz {
inline sonarfusion::DaemonConfig checkpointFuzzConfig() {
    sonarfusion::DaemonConfig c;
    c.mapper.map.nx = c.mapper.map.ny = c.mapper.map.nz = 8;
    c.mapper.nav_buffer_capacity = 16;
    c.mapper.detector.seabed_capacity = 64;
    c.mapper.detector.min_seabed_echoes = 8;
    c.mapper.detector.risen_capacity = 8;
    c.mapper.detector.min_risen_echoes = 2;
    c.fls_pending_slots = 2;
    c.ps_pending_slots = 4;
    return c;
}
}  // namespace sffuzz
