// End-face angle of a reconstruction (docs/design.md, "Evaluation"; docs/evaluation.md).
//
// True end faces: the object's triangles whose unit normal has |n.a| >= 0.5
// along the horizontal along-track axis a, split by the sign of n.a into the
// front (+a) and back (-a) face. Normals are oriented away from the object's
// vertex centroid (fine for the convex test objects).
//
// Predicted voxels used for one face: object voxels whose centre
//  - lies between the face's top and bottom depth, at least `edge_margin`
//    voxels away from both (the top edge and the seabed contact are left out),
//  - lies within the face's lateral extent shrunk by the same margin,
//  - is between `inward_window` m inside and `outward_window` m outside the
//    true face plane, measured along the outward direction;
// and of those, per (depth row, lateral column) only the outermost voxel: the
// face the map shows from outside, including any false slope in front of it.
// A plane is fitted to those centres; the angle is faceAngleDeg. No angle
// (null) with fewer than 2 rows or 2 columns of such voxels.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "grid.hpp"
#include "mesh.hpp"

namespace sonarfusion::eval {

struct EndFace {
    Eigen::Vector3d outward;   // horizontal unit vector pointing out of the object
    Eigen::Vector3d point;     // on the true face plane (area-weighted centroid)
    Eigen::Vector3d normal;    // true outward unit normal
    double true_angle_deg = 0.0;
    double z_top = 0.0, z_bottom = 0.0;           // NED depth range of the face
    double lateral_min = 0.0, lateral_max = 0.0;  // along lateralAxis(outward)
};

struct EndFaceSelection {
    double outward_window = 1.0;   // m in front of the true face (reaches false slopes)
    double inward_window = 0.3;    // m behind it
    double edge_margin = 1.0;      // voxels kept clear of the face's edges
};

struct FaceAngle {
    std::optional<double> angle_deg;
    double true_angle_deg = 0.0;
    std::size_t points = 0;  // voxel centres in the fit
};

[[nodiscard]] Eigen::Vector3d lateralAxis(const Eigen::Vector3d& outward);
[[nodiscard]] std::vector<EndFace> findEndFaces(const TriangleMesh& object, const Eigen::Vector3d& along_track);
// The voxel centres the fit uses (exposed for figures and tests).
[[nodiscard]] std::vector<Eigen::Vector3d> selectEndFaceVoxels(const GridSpec& grid, const VoxelMask& predicted,
                                                               const EndFace& face, const EndFaceSelection& sel);
[[nodiscard]] FaceAngle measureEndFace(const GridSpec& grid, const VoxelMask& predicted, const EndFace& face,
                                       const EndFaceSelection& sel = {});

}  // namespace sonarfusion::eval
