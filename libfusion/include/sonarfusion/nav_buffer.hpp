// Fixed-capacity, time-ordered NAV history; the pose at a sonar message's
// utime is interpolated between the two samples that bracket it.
#pragma once

#include <cstdint>
#include <vector>

#include "sonarfusion/pose.hpp"
#include "sonarfusion/state_codec.hpp"

namespace sonarfusion {

// Checkpoint encoding of one NAV sample; reading refuses a non-finite pose.
inline void saveTimedPose(StateWriter& w, const TimedPose& p) {
    w.pod(p.utime);
    for (int i = 0; i < 3; ++i) w.pod(p.pose.position[i]);
    w.pod(p.pose.roll);
    w.pod(p.pose.pitch);
    w.pod(p.pose.yaw);
}
[[nodiscard]] inline bool loadTimedPose(StateReader& r, TimedPose& p) {
    return r.pod(p.utime) && r.pod(p.pose.position[0]) && r.pod(p.pose.position[1]) && r.pod(p.pose.position[2]) &&
           r.pod(p.pose.roll) && r.pod(p.pose.pitch) && r.pod(p.pose.yaw) && p.pose.isFinite();
}

enum class PoseLookup { Ok, NoBracket, GapTooLarge };

class NavBuffer {
public:
    NavBuffer(int capacity, int64_t max_gap_us);

    // False (nothing stored) for a non-finite pose or a utime not after the newest.
    enum class AddResult { Ok, NonFinite, OutOfOrder };
    AddResult add(const TimedPose& p);
    [[nodiscard]] PoseLookup poseAt(int64_t utime, Pose& out) const;
    [[nodiscard]] int size() const { return count_; }
    [[nodiscard]] bool empty() const { return count_ == 0; }
    [[nodiscard]] const TimedPose& newest() const { return at(count_ - 1); }
    void clear() { count_ = 0; head_ = 0; }
    void saveState(StateWriter& w) const;
    [[nodiscard]] bool loadState(StateReader& r);

private:
    [[nodiscard]] const TimedPose& at(int i) const {  // 0 = oldest
        return ring_[(head_ + i) % static_cast<int>(ring_.size())];
    }
    std::vector<TimedPose> ring_;
    int head_ = 0, count_ = 0;
    int64_t max_gap_us_;
};

}  // namespace sonarfusion
