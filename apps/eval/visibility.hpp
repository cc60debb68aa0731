// Which parts of the object surface a run could see (docs/design.md,
// "Evaluation": recall is
// measured on the surface visible from at least one sensor pose; shadowed
// faces are excluded as in the paper).
//
// The object surface is sampled densely (centroids of a regular subdivision of
// every triangle, `sample_spacing` apart). A sample is seen by a sensor when,
// for at least one pose, it lies inside that sensor's field of view (bearing,
// elevation, range) and the segment from the sensor to the sample, stopped
// `self_hit_margin` short, meets no triangle of the occluders (objects and
// seabed) — CGAL AABB tree. The voxel-level mask is made in ground_truth.hpp.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "mesh.hpp"
#include "sonarfusion/config.hpp"

namespace sonarfusion::eval {

// Field of view in the sensor frame (x boresight without tilt, y starboard,
// z down): bearing = atan2(y, x); elevation = atan2(z, hypot(x, y)), positive
// down, tilt included; range = |p|.
struct SensorFov {
    double bearing_min = 0, bearing_max = 0;
    double elevation_min = 0, elevation_max = 0;
    double range_min = 0, range_max = 0;

    // FLS: bearing +-theta_F/2, elevation tilt + [phi_min, phi_max] (Eqs. 1-4).
    [[nodiscard]] static SensorFov fls(const FlsGeometry& g);
    // PS: bearing [theta_min, theta_max], elevation tilt + the head's sector
    // [phi_p min, max] (Eqs. 10-11; the head sweeps the whole sector).
    [[nodiscard]] static SensorFov ps(const PsGeometry& g);
    [[nodiscard]] bool contains(const Eigen::Vector3d& p_sensor) const;
};

struct SensorPose {
    Eigen::Vector3d position = Eigen::Vector3d::Zero();                 // NED
    Eigen::Matrix3d world_from_sensor = Eigen::Matrix3d::Identity();  // sensor frame as above
};

struct SensorRun {
    std::string name;  // "fls", "ps"
    SensorFov fov;
    std::vector<SensorPose> poses;
};

struct VisibilityOptions {
    double sample_spacing = 0.025;    // m between surface samples (a quarter voxel)
    double self_hit_margin = 0.005;   // m: the sight line stops this short of the sample
    double min_pose_spacing = 0.025;  // m: poses closer than this to the last kept one are skipped
    int threads = 2;                  // worker threads over the samples (results do not depend on it)
};

struct SurfaceSample {
    Eigen::Vector3d point;
    uint32_t seen_by = 0;  // bit k set: runs[k] saw it
};

[[nodiscard]] std::vector<SurfaceSample> sampleVisibleSurface(const std::vector<TriangleMesh>& targets,
                                                              const std::vector<TriangleMesh>& occluders,
                                                              const std::vector<SensorRun>& runs,
                                                              const VisibilityOptions& options = {});

}  // namespace sonarfusion::eval
