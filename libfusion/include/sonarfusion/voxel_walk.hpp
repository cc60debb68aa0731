// Integer voxel traversal of a segment (Amanatides & Woo 1987), clipped to the
// grid. Chosen over 3D Bresenham because it visits every voxel the segment
// passes through (Bresenham may step diagonally past a corner voxel), so no
// voxel between the sensor and the echo escapes carving.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <cstddef>
#include <limits>

#include "sonarfusion/voxel_map.hpp"

namespace sonarfusion {

struct WalkResult {
    bool end_in_map = false;   // the voxel holding `b` is inside the grid
    std::size_t end_voxel = 0; // its linear index, when end_in_map
    int visited = 0;           // voxels passed to the visitor
};

// Calls visit(linear_index, s_mid) for each voxel the segment a->b crosses
// inside the grid, in order from a, EXCEPT the voxel that holds b. s_mid in
// [0, 1] is the middle of the segment's passage through the voxel, as a
// fraction of |b - a| (Eq. 13's normalised distance t).
template <class Visit>
WalkResult walkSegment(const VoxelMap& map, const Eigen::Vector3d& a, const Eigen::Vector3d& b, Visit&& visit) {
    WalkResult res;
    const Eigen::Vector3d A = (a - map.origin()) / map.resolution();
    const Eigen::Vector3d B = (b - map.origin()) / map.resolution();
    if (!A.allFinite() || !B.allFinite()) return res;
    const int n[3] = {map.nx(), map.ny(), map.nz()};

    VoxelIndex end_idx;
    res.end_in_map = map.worldToIndex(b, end_idx);
    if (res.end_in_map) res.end_voxel = map.linear(end_idx);

    // Clip s in [0, 1] to the grid box [0, n] (slab test).
    const Eigen::Vector3d d = B - A;
    double s0 = 0.0, s1 = 1.0;
    for (int i = 0; i < 3; ++i) {
        if (std::fabs(d[i]) < 1e-12) {
            if (A[i] < 0.0 || A[i] >= n[i]) return res;
            continue;
        }
        double t0 = (0.0 - A[i]) / d[i], t1 = (n[i] - A[i]) / d[i];
        if (t0 > t1) std::swap(t0, t1);
        s0 = std::max(s0, t0);
        s1 = std::min(s1, t1);
    }
    if (s0 >= s1) return res;

    const Eigen::Vector3d start = A + s0 * d;
    int v[3], step[3];
    double s_next[3], s_delta[3];
    for (int i = 0; i < 3; ++i) {
        v[i] = static_cast<int>(std::floor(start[i]));
        if (v[i] < 0) v[i] = 0;
        if (v[i] >= n[i]) v[i] = n[i] - 1;
        if (d[i] > 0.0) {
            step[i] = 1;
            s_delta[i] = 1.0 / d[i];
            s_next[i] = (v[i] + 1 - A[i]) / d[i];
        } else if (d[i] < 0.0) {
            step[i] = -1;
            s_delta[i] = -1.0 / d[i];
            s_next[i] = (v[i] - A[i]) / d[i];
        } else {
            step[i] = 0;
            s_delta[i] = std::numeric_limits<double>::infinity();
            s_next[i] = std::numeric_limits<double>::infinity();
        }
    }

    double s_enter = s0;
    const int max_steps = n[0] + n[1] + n[2] + 3;
    for (int guard = 0; guard < max_steps; ++guard) {
        const int axis = (s_next[0] < s_next[1]) ? (s_next[0] < s_next[2] ? 0 : 2) : (s_next[1] < s_next[2] ? 1 : 2);
        const double s_exit = std::min(s_next[axis], s1);
        const std::size_t lin = (static_cast<std::size_t>(v[2]) * n[1] + v[1]) * n[0] + v[0];
        if (res.end_in_map && lin == res.end_voxel) break;  // Eq. 13 skips the echo's voxel
        visit(lin, 0.5 * (s_enter + s_exit));
        ++res.visited;
        if (s_next[axis] >= s1) break;  // the segment ends (or leaves the grid) in this voxel
        v[axis] += step[axis];
        if (v[axis] < 0 || v[axis] >= n[axis]) break;
        s_enter = s_next[axis];
        s_next[axis] += s_delta[axis];
    }
    return res;
}

}  // namespace sonarfusion
