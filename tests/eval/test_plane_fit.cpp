// Plane fit and end-face angle.
#include <gtest/gtest.h>

#include "end_face.hpp"
#include "eval_test_helpers.hpp"
#include "plane_fit.hpp"
#include "voxelise.hpp"

namespace sonarfusion::eval {
namespace {

constexpr double kDeg = M_PI / 180.0;

// Voxels whose centres lie within half a voxel (along x) of a face inclined at
// 60 deg from the horizontal, facing +x (NED: up is -z).
TEST(PlaneFit, SyntheticSixtyDegreeVoxelFace) {
    const GridSpec g{Eigen::Vector3d::Zero(), 0.1, 40, 20, 30};
    const Eigen::Vector3d normal(std::sin(60 * kDeg), 0.0, -std::cos(60 * kDeg));
    const Eigen::Vector3d on_plane(2.0, 1.0, 1.5);
    std::vector<Eigen::Vector3d> centres;
    for (std::size_t i = 0; i < g.size(); ++i) {
        const Eigen::Vector3d c = g.centre(i);
        if (std::abs(normal.dot(c - on_plane) / normal.x()) <= 0.05 + 1e-9) centres.push_back(c);
    }
    ASSERT_GT(centres.size(), 100u);
    const auto fit = fitPlane(centres);
    ASSERT_TRUE(fit.has_value());
    EXPECT_NEAR(faceAngleDeg(fit->normal, Eigen::Vector3d::UnitX()), 60.0, 0.5);
}

TEST(PlaneFit, FaceAngleConvention) {
    const Eigen::Vector3d out = Eigen::Vector3d::UnitX();
    EXPECT_NEAR(faceAngleDeg(Eigen::Vector3d::UnitX(), out), 90.0, 1e-12);    // wall
    EXPECT_NEAR(faceAngleDeg(-Eigen::Vector3d::UnitX(), out), 90.0, 1e-12);   // sign-free
    EXPECT_NEAR(faceAngleDeg(Eigen::Vector3d(1, 0, -1).normalized(), out), 45.0, 1e-12);  // leans out
    EXPECT_NEAR(faceAngleDeg(Eigen::Vector3d(1, 0, 1).normalized(), out), 135.0, 1e-12);  // overhang
}

TEST(PlaneFit, TooFewPoints) { EXPECT_FALSE(fitPlane({{0, 0, 0}, {1, 0, 0}}).has_value()); }

class SlopeBoxFaces : public ::testing::TestWithParam<double> {};

// A perfect map of a slope box (its voxelised solid) gives back alpha on both
// end faces; the voxel staircase costs well under a degree.
TEST_P(SlopeBoxFaces, PerfectMapRecoversAlpha) {
    const double alpha = GetParam();
    const GridSpec g{Eigen::Vector3d(-1.0, -1.0, 18.5), 0.1, 40, 30, 20};
    const TriangleMesh box = loadMesh(test::writeSlopeBox("slope_box", {0.0, 0.0, 20.0}, 2.0, 1.2, 1.0, alpha));
    const std::vector<EndFace> faces = findEndFaces(box, Eigen::Vector3d::UnitX());
    ASSERT_EQ(faces.size(), 2u);
    const MeshVoxels truth = voxeliseMesh(box, g);
    for (const EndFace& f : faces) {
        EXPECT_NEAR(f.true_angle_deg, alpha, 1e-9);
        EXPECT_NEAR(f.z_top, 19.0, 1e-12);
        EXPECT_NEAR(f.z_bottom, 20.0, 1e-12);
        const FaceAngle a = measureEndFace(g, truth.solid, f);
        ASSERT_TRUE(a.angle_deg.has_value());
        EXPECT_NEAR(*a.angle_deg, alpha, 1.0) << "outward " << f.outward.transpose();
        EXPECT_GE(a.points, 8u * 10u);  // rows 19.15..19.85 (8) x columns 0.15..1.05 (10)
    }
}

INSTANTIATE_TEST_SUITE_P(Alpha, SlopeBoxFaces, ::testing::Values(90.0, 60.0),
                         [](const ::testing::TestParamInfo<double>& i) {
                             return "Alpha" + std::to_string(static_cast<int>(i.param));
                         });

// An FLS-like false slope: voxels in front of a vertical face, falling away at
// 45 deg from the top edge. The outermost voxels are the slope, not the wall.
TEST(EndFace, FalseSlopeLowersTheAngle) {
    const GridSpec g{Eigen::Vector3d(-1.0, -1.0, 18.5), 0.1, 50, 30, 20};
    const TriangleMesh box = loadMesh(test::writeBox("box90", {0.0, 0.0, 19.0}, {2.0, 1.2, 20.0}));
    VoxelMask predicted = voxeliseMesh(box, g).surface;
    for (std::size_t i = 0; i < g.size(); ++i) {
        const Eigen::Vector3d c = g.centre(i);
        const double out = c.x() - 2.0, below_top = c.z() - 19.0;
        if (out > 0 && c.y() > 0 && c.y() < 1.2 && below_top > 0 && below_top < 1.0 && std::abs(out - below_top) < 0.05)
            predicted[i] = 1;
    }
    const std::vector<EndFace> faces = findEndFaces(box, Eigen::Vector3d::UnitX());
    const EndFace& front = faces[0].outward.x() > 0 ? faces[0] : faces[1];
    const FaceAngle a = measureEndFace(g, predicted, front);
    ASSERT_TRUE(a.angle_deg.has_value());
    EXPECT_NEAR(*a.angle_deg, 45.0, 3.0);
}

TEST(EndFace, NoVoxelsGivesNull) {
    const GridSpec g{Eigen::Vector3d(-1.0, -1.0, 18.5), 0.1, 40, 30, 20};
    const TriangleMesh box = loadMesh(test::writeBox("box90_empty", {0.0, 0.0, 19.0}, {2.0, 1.2, 20.0}));
    const FaceAngle a = measureEndFace(g, VoxelMask(g.size(), 0), findEndFaces(box, Eigen::Vector3d::UnitX())[0]);
    EXPECT_FALSE(a.angle_deg.has_value());
    EXPECT_EQ(a.points, 0u);
}

}  // namespace
}  // namespace sonarfusion::eval
