#include "sonarfusion/object_detector.hpp"

#include <stdexcept>

namespace sonarfusion {

ObjectDetector::ObjectDetector(const DetectorConfig& cfg) : cfg_(cfg) {
    if (cfg.baseline_window < 1 || cfg.min_baseline_pings < 1 || cfg.min_baseline_pings > cfg.baseline_window ||
        cfg.min_consecutive < 1 || !(cfg.rise_threshold > 0.0))
        throw std::invalid_argument("detector: need 1 <= min_baseline_pings <= baseline_window, min_consecutive >= 1, rise_threshold > 0");
    ring_.assign(cfg.baseline_window, 0.0);
}

void ObjectDetector::reset() {
    ring_count_ = ring_next_ = 0;
    ring_sum_ = 0.0;
    risen_run_ = 0;
    risen_sum_.setZero();
    detection_.reset();
}

std::optional<double> ObjectDetector::baseline() const {
    if (ring_count_ < cfg_.min_baseline_pings) return std::nullopt;
    return ring_sum_ / ring_count_;
}

bool ObjectDetector::addEchoPoint(const Eigen::Vector3d& p) {
    if (detection_ || !p.allFinite()) return false;
    const std::optional<double> base = baseline();
    // NED: up is -z, so an echo that rose above the seabed has a smaller z.
    if (base && p.z() < *base - cfg_.rise_threshold) {
        ++risen_run_;
        risen_sum_ += p;
        if (risen_run_ >= cfg_.min_consecutive) {
            detection_ = risen_sum_ / risen_run_;
            return true;
        }
        return false;
    }
    // A seabed echo: it ends any rising run and feeds the baseline (risen
    // echoes never do, so an object cannot drag the baseline up to itself).
    risen_run_ = 0;
    risen_sum_.setZero();
    if (ring_count_ == cfg_.baseline_window) ring_sum_ -= ring_[ring_next_];
    else ++ring_count_;
    ring_[ring_next_] = p.z();
    ring_sum_ += p.z();
    ring_next_ = (ring_next_ + 1) % cfg_.baseline_window;
    return false;
}

}  // namespace sonarfusion
