// Small builders shared by the unit tests.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <vector>

#include "sonarfusion/config.hpp"
#include "sonarfusion/fls_model.hpp"
#include "sonarfusion/pose.hpp"
#include "sonarfusion/ps_model.hpp"
#include "sonarfusion/voxel_map.hpp"

namespace sonarfusion::test {

inline TimedPose poseAt(int64_t utime, double x, double y, double z, double yaw = 0.0) {
    TimedPose p;
    p.utime = utime;
    p.pose.position = Eigen::Vector3d(x, y, z);
    p.pose.yaw = yaw;
    return p;
}

// The default map (100^3 at 0.1 m) with its origin at (0, 0, 0): voxel i spans
// [0.1 i, 0.1 (i + 1)) on each axis.
inline VoxelMap originMap() {
    VoxelMap m{MapConfig{}};
    m.initialiseAt(Eigen::Vector3d(5.0, 5.0, 5.0));
    return m;
}

struct OwnedFrame {
    std::vector<uint8_t> pixels;
    FlsFrame view;
};

inline OwnedFrame blankFrame(const FlsGeometry& g, int64_t utime) {
    OwnedFrame f;
    f.pixels.assign(static_cast<std::size_t>(g.rows) * g.beams, 0);
    f.view.utime = utime;
    f.view.rows = g.rows;
    f.view.cols = g.beams;
    f.view.data = f.pixels.data();
    f.view.data_size = f.pixels.size();
    return f;
}

inline void setPixel(OwnedFrame& f, int row, int col, uint8_t v) {
    f.pixels[static_cast<std::size_t>(row) * f.view.cols + col] = v;
}

struct OwnedPing {
    std::vector<uint8_t> bins;
    PsPing view;
};

inline OwnedPing blankPing(int bins, double range_max, int64_t utime, double head_angle) {
    OwnedPing p;
    p.bins.assign(bins, 0);
    p.view.utime = utime;
    p.view.head_angle = head_angle;
    p.view.range_min = 0.0;
    p.view.range_max = range_max;
    p.view.bins = bins;
    p.view.intensity = p.bins.data();
    return p;
}

}  // namespace sonarfusion::test

namespace sonarfusion::test {

// A flat seabed at depth 20 m with an axis-aligned 2.0 x 1.2 x 1.0 m box on it,
// centred at the origin: just enough world to drive the pipeline analytically.
struct BoxWorld {
    double seabed = 20.0;
    Eigen::Vector3d box_min{-1.0, -0.6, 19.0}, box_max{1.0, 0.6, 20.0};

    // Distance along the unit ray to the first surface, or -1 when none within max_range.
    double cast(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double max_range) const {
        double best = -1.0;
        if (d.z() > 1e-9) best = (seabed - o.z()) / d.z();
        double t0 = 0.0, t1 = 1e9;
        bool hit = true;
        for (int i = 0; i < 3 && hit; ++i) {
            if (std::fabs(d[i]) < 1e-12) {
                hit = o[i] >= box_min[i] && o[i] <= box_max[i];
                continue;
            }
            double a = (box_min[i] - o[i]) / d[i], b = (box_max[i] - o[i]) / d[i];
            if (a > b) std::swap(a, b);
            t0 = std::max(t0, a);
            t1 = std::min(t1, b);
            hit = t0 <= t1;
        }
        if (hit && (best < 0.0 || t0 < best)) best = t0;
        return best > max_range ? -1.0 : best;
    }
};

// Several such boxes along the track (survey tests): the nearest surface of any.
struct BoxesWorld {
    std::vector<BoxWorld> boxes;
    explicit BoxesWorld(std::initializer_list<double> centres_x) {
        for (double x : centres_x) {
            BoxWorld b;
            b.box_min.x() += x;
            b.box_max.x() += x;
            boxes.push_back(b);
        }
    }
    double cast(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double max_range) const {
        double best = -1.0;
        for (const BoxWorld& b : boxes) {
            const double r = b.cast(o, d, max_range);
            if (r >= 0.0 && (best < 0.0 || r < best)) best = r;
        }
        return best;
    }
};

// The PS head's angle at ping `i` of a sector scan from -20 to 20 deg and back, 1 deg per ping (rad).
inline double sectorScanHead(int i) {
    const int phase = i % 80;
    return (phase < 40 ? -20 + phase : 60 - phase) * M_PI / 180.0;
}

// Vehicle at 3.12 m altitude heading north, `x` metres along track.
inline TimedPose trackPose(int64_t utime, double x) { return poseAt(utime, x, 0.0, 20.0 - 3.12); }

template <class World>
inline OwnedPing simulatePing(const World& w, const PsModel& m, const Pose& pose, int64_t utime, double head) {
    OwnedPing p = blankPing(500, 10.0, utime, head);
    const Eigen::Isometry3d s = sensorToWorld(pose, Mounting{});
    const double r = w.cast(s.translation(), s.linear() * m.centreDirection(head), 10.0);
    if (r > 0.0) {
        const int bin = static_cast<int>(std::lround(r / 10.0 * 499));
        for (int b = std::max(0, bin - 1); b <= std::min(499, bin + 1); ++b) p.bins[b] = b == bin ? 240 : 200;
    }
    return p;
}

template <class World>
inline OwnedFrame simulateFrame(const World& w, const FlsGeometry& g, const FlsModel& m, const Pose& pose,
                                int64_t utime) {
    OwnedFrame f = blankFrame(g, utime);
    const Eigen::Isometry3d s = sensorToWorld(pose, Mounting{});
    for (int c = 0; c < g.beams; ++c) {
        for (int e = 0; e <= 14; ++e) {  // 15 rays over the vertical aperture
            const double down = g.tilt + g.elevation_min + e * (g.elevation_max - g.elevation_min) / 14.0;
            const double th = m.bearingOfColumn(c);
            const Eigen::Vector3d d(std::cos(down) * std::cos(th), std::cos(down) * std::sin(th), std::sin(down));
            const double r = w.cast(s.translation(), s.linear() * d, g.range_max);
            if (r < g.range_min) continue;
            const int row = static_cast<int>(std::lround((g.range_max - r) / (g.range_max - g.range_min) * (g.rows - 1)));
            setPixel(f, row, c, 220);
        }
    }
    return f;
}

}  // namespace sonarfusion::test
