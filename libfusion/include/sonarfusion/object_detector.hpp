// Paper 2.1: before any map exists, each PS ping's strongest echo becomes a
// world point. A running seabed baseline of their heights is kept; when the
// heights rise above it for several pings in a row, an object is declared and
// the map is initialised around it.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "sonarfusion/config.hpp"

namespace sonarfusion {

class ObjectDetector {
public:
    explicit ObjectDetector(const DetectorConfig& cfg);  // ring buffer allocated here

    // Feeds one echo point (NED). Returns true on the ping that declares an object.
    bool addEchoPoint(const Eigen::Vector3d& p);
    void reset();

    [[nodiscard]] bool detected() const { return detection_.has_value(); }
    // Mean position of the risen echoes that declared the object.
    [[nodiscard]] const std::optional<Eigen::Vector3d>& detection() const { return detection_; }
    // Running seabed depth (NED z, m); nothing until the baseline has enough pings.
    [[nodiscard]] std::optional<double> baseline() const;

private:
    DetectorConfig cfg_;
    std::vector<double> ring_;  // seabed depths of recent non-risen echoes
    int ring_count_ = 0;
    int ring_next_ = 0;
    double ring_sum_ = 0.0;
    int risen_run_ = 0;
    Eigen::Vector3d risen_sum_ = Eigen::Vector3d::Zero();
    std::optional<Eigen::Vector3d> detection_;
};

}  // namespace sonarfusion
