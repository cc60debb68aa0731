// The order the daemon processes sonar messages in, one definition for the
// daemon (MapperNode::flushOrdered) and the tools that replay a log the same
// way (tools/bench's loadScenarioLog): by utime; at equal utime a PS ping
// before an FLS frame; within a channel by seq. A message is released once a
// NAV sample newer than it has arrived (the pose is then interpolated, never
// extrapolated). The map then never depends on how the transport interleaved
// the channels (docs/mapper-config.md, "Ordering and determinism").
#pragma once

#include <cstdint>

namespace sonarfusion {

enum class SonarKind : int { Ps = 0, Fls = 1 };

struct SonarKey {
    int64_t utime;
    SonarKind kind;
    int64_t seq;
};

[[nodiscard]] inline bool sonarBefore(const SonarKey& a, const SonarKey& b) {
    if (a.utime != b.utime) return a.utime < b.utime;
    if (a.kind != b.kind) return a.kind < b.kind;
    return a.seq < b.seq;
}

// Whether NAV up to `newest_nav_utime` brackets a message of `utime`.
[[nodiscard]] inline bool sonarReleased(int64_t utime, int64_t newest_nav_utime) { return utime < newest_nav_utime; }

}  // namespace sonarfusion
