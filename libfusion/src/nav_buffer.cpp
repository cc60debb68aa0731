#include "sonarfusion/nav_buffer.hpp"

#include <stdexcept>

namespace sonarfusion {

NavBuffer::NavBuffer(int capacity, int64_t max_gap_us) : max_gap_us_(max_gap_us) {
    if (capacity < 2) throw std::invalid_argument("nav buffer capacity must be >= 2");
    ring_.resize(capacity);
}

NavBuffer::AddResult NavBuffer::add(const TimedPose& p) {
    if (!p.pose.isFinite()) return AddResult::NonFinite;
    if (count_ > 0 && p.utime <= newest().utime) return AddResult::OutOfOrder;
    const int cap = static_cast<int>(ring_.size());
    if (count_ < cap) {
        ring_[(head_ + count_) % cap] = p;
        ++count_;
    } else {
        ring_[head_] = p;  // overwrite the oldest
        head_ = (head_ + 1) % cap;
    }
    return AddResult::Ok;
}

PoseLookup NavBuffer::poseAt(int64_t utime, Pose& out) const {
    if (count_ == 0 || utime < at(0).utime || utime > newest().utime) return PoseLookup::NoBracket;
    // Binary search for the first sample at or after utime.
    int lo = 0, hi = count_ - 1;
    while (lo < hi) {
        const int mid = (lo + hi) / 2;
        if (at(mid).utime < utime) lo = mid + 1;
        else hi = mid;
    }
    const TimedPose& after = at(lo);
    if (after.utime == utime) {
        out = after.pose;
        return PoseLookup::Ok;
    }
    const TimedPose& before = at(lo - 1);  // lo > 0 because utime > at(0).utime here
    // Unsigned difference: utimes come off the network and may be anything.
    if (static_cast<uint64_t>(after.utime) - static_cast<uint64_t>(before.utime) > static_cast<uint64_t>(max_gap_us_))
        return PoseLookup::GapTooLarge;
    out = interpolate(before, after, utime);
    return PoseLookup::Ok;
}

void NavBuffer::saveState(StateWriter& w) const {
    w.pod(static_cast<uint64_t>(ring_.size()));
    w.pod(count_);
    for (int i = 0; i < count_; ++i) saveTimedPose(w, at(i));  // oldest first
}

bool NavBuffer::loadState(StateReader& r) {
    int c = 0;
    if (!r.expect(ring_.size()) || !r.pod(c) || c < 0 || c > static_cast<int>(ring_.size())) return false;
    head_ = 0;
    count_ = 0;
    for (int i = 0; i < c; ++i) {
        TimedPose p;
        if (!loadTimedPose(r, p)) return false;
        if (add(p) != AddResult::Ok) return false;  // must be finite and in order, as when it was written
    }
    return true;
}

}  // namespace sonarfusion
