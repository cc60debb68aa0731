// Shared by the daemon-core tests: LCM-encode a message and hand it to a node
// the way the live loop does.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "mapper_node.hpp"

namespace sonarfusion::test {

template <class Msg>
std::vector<uint8_t> encode(const Msg& msg) {
    std::vector<uint8_t> buf(msg.getEncodedSize());
    msg.encode(buf.data(), 0, static_cast<int>(buf.size()));
    return buf;
}

template <class Msg>
void send(MapperNode& node, const std::string& channel, const Msg& msg) {
    const auto b = encode(msg);
    node.handle(channel, b.data(), b.size());
}

// A ping as the configured PS would send it (its geometry from the config),
// all bins silent: callers put their echoes in.
inline ps_ping_t psPing(const MapperConfig& c, int64_t utime, int64_t seq, double head_angle = 0.0) {
    ps_ping_t p{};
    p.utime = utime;
    p.seq = seq;
    p.tilt = static_cast<float>(c.ps.tilt);
    p.fan_min = static_cast<float>(c.ps.fan_min);
    p.fan_max = static_cast<float>(c.ps.fan_max);
    p.range_min = static_cast<float>(c.ps.range_min);
    p.range_max = static_cast<float>(c.ps.range_max);
    p.head_angle = static_cast<float>(head_angle);
    p.num_bins = c.ps.bins;
    p.intensity.assign(static_cast<std::size_t>(c.ps.bins), 0);
    return p;
}

}  // namespace sonarfusion::test
