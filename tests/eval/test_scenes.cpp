// Scenes beyond one convex box: meshes with several parts, several object
// meshes, no object at all; and the visibility pass's shortcuts (field-of-view
// pre-test, sliver sampling, threads) against plain definitions.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>
#include <random>

#include "eval_test_helpers.hpp"
#include "ground_truth.hpp"
#include "map_scoring.hpp"
#include "metrics.hpp"
#include "report.hpp"
#include "visibility.hpp"
#include "voxelise.hpp"

namespace sonarfusion::eval {
namespace {

using Boxes = std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>>;

// Several axis-aligned boxes [lo, hi] in one OFF file, each with its own 8
// vertices (corners that coincide are merged by the reader's repair).
std::string writeBoxes(const std::string& name, const Boxes& boxes) {
    std::vector<Eigen::Vector3d> v;
    std::vector<std::vector<int>> f;
    for (const auto& [lo, hi] : boxes) {
        const int b = static_cast<int>(v.size());
        for (int k = 0; k < 8; ++k)
            v.emplace_back(k & 1 ? hi.x() : lo.x(), k & 2 ? hi.y() : lo.y(), k & 4 ? hi.z() : lo.z());
        for (const auto& q : std::vector<std::vector<int>>{{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                                           {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}})
            f.push_back({b + q[0], b + q[1], b + q[2], b + q[3]});
    }
    return test::writeOff(name, v, f);
}

const GridSpec kGrid{Eigen::Vector3d(0.0, 0.0, 18.0), 0.1, 40, 30, 25};

// Two disconnected closed boxes in one file: both solids, two objects.
TEST(MultiPart, TwoDisconnectedBoxesInOneFile) {
    const TriangleMesh m = loadMesh(writeBoxes("two_boxes", {{{0.5, 0.5, 19.0}, {1.0, 1.0, 19.5}},    // 5x5x5
                                                             {{2.0, 1.0, 19.2}, {2.3, 1.3, 19.5}}}));  // 3x3x3
    const MeshVoxels v = voxeliseMesh(m, kGrid);
    EXPECT_TRUE(v.closed);
    EXPECT_EQ(countSet(v.solid), 125u + 27u);
    EXPECT_EQ(countObjects({m}), 1 + 1);
}

// A cross of two overlapping bars: one parity test over both surfaces would
// call the overlap outside; the union of the parts' insides does not.
TEST(MultiPart, OverlappingBarsAreOneSolid) {
    const TriangleMesh m = loadMesh(writeBoxes("cross", {{{0.5, 1.0, 19.0}, {2.5, 1.2, 19.2}},    // 20x2x2
                                                         {{1.4, 0.2, 19.0}, {1.6, 2.2, 19.2}}}));  // 2x20x2
    const MeshVoxels v = voxeliseMesh(m, kGrid);
    EXPECT_TRUE(v.closed);
    EXPECT_EQ(countSet(v.solid), 80u + 80u - 8u);
    EXPECT_TRUE(v.solid[kGrid.linear(15, 11, 10)]);  // in the overlap
    EXPECT_EQ(countObjects({m}), 1);
}

// An open frame (arch) of three closed bars that touch: the legs' top faces lie
// on the beam's bottom face, corners shared. Non-manifold where they meet, yet
// each bar is closed and the arch is one object.
TEST(MultiPart, ArchOfTouchingBars) {
    const TriangleMesh m = loadMesh(writeBoxes("arch", {{{1.0, 1.0, 19.2}, {1.2, 1.2, 20.0}},    // leg 2x2x8
                                                        {{1.8, 1.0, 19.2}, {2.0, 1.2, 20.0}},    // leg 2x2x8
                                                        {{1.0, 1.0, 19.0}, {2.0, 1.2, 19.2}}}));  // beam 10x2x2
    const MeshVoxels v = voxeliseMesh(m, kGrid);
    EXPECT_TRUE(v.closed);
    EXPECT_EQ(countSet(v.solid), 32u + 32u + 40u);
    EXPECT_FALSE(v.solid[kGrid.linear(15, 10, 15)]);  // under the beam, between the legs
    EXPECT_EQ(countObjects({m}), 1);
}

// Two object meshes in one scene: union of solids, each seen, two objects.
TEST(MultiPart, TwoObjectMeshesInOneScene) {
    const std::string a = test::writeBox("scene_a", {0.5, 0.5, 19.5}, {1.0, 1.0, 20.0});
    const std::string b = test::writeBox("scene_b", {2.5, 1.5, 19.5}, {3.0, 2.0, 20.0});
    const std::string seabed =
        test::writeOff("scene_seabed", {{-5, -5, 20.0}, {9, -5, 20.0}, {9, 9, 20.0}, {-5, 9, 20.0}}, {{0, 1, 2, 3}});
    const SensorRun above{"all", {-M_PI, M_PI, -M_PI / 2, M_PI / 2, 0.0, 100.0},
                          {{Eigen::Vector3d(1.75, 1.25, 17.0), Eigen::Matrix3d::Identity()}}};
    const SceneTruth scene = makeSceneTruth("two", {a, b}, {seabed}, {above}, Eigen::Vector3d::UnitX());
    EXPECT_EQ(scene.objects_true, 2);
    const GroundTruth gt = groundTruthInGrid(scene, kGrid);
    EXPECT_EQ(countSet(gt.object.solid), 2u * 125u);
    // Both tops (5x5 each) are seen from above.
    EXPECT_TRUE(gt.visible[kGrid.linear(7, 7, 15)]);
    EXPECT_TRUE(gt.visible[kGrid.linear(27, 17, 15)]);
    EXPECT_FALSE(gt.visible[kGrid.linear(7, 7, 19)]);  // on the seabed
}

// A mesh from another project, modelled in millimetres about its own origin
// with y up, placed by the scenario (mesh::Placement: scale, rotation,
// translation): the same truth as the same box written in the world's metres.
TEST(MultiPart, PlacedMeshGivesTheSameTruthAsTheMeshInPlace) {
    // 0.5 (along) x 0.3 (up) x 0.4 (across) m, bottom on the seabed at 20 m.
    const std::string in_place = test::writeBox("in_place", {0.5, 0.5, 19.7}, {1.0, 0.9, 20.0});
    const std::string mm_y_up = test::writeBox("mm_y_up", {-250, -150, -200}, {250, 150, 200});
    Placement where;
    where.scale = 0.001;
    // Roll -90 deg: the file's +y (up) becomes NED -z, its +z becomes +y.
    where.pose.linear() = Eigen::AngleAxisd(-M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
    where.pose.translation() = Eigen::Vector3d(0.75, 0.7, 19.85);
    const std::string seabed =
        test::writeOff("placed_seabed", {{-5, -5, 20.0}, {9, -5, 20.0}, {9, 9, 20.0}, {-5, 9, 20.0}}, {{0, 1, 2, 3}});
    const SensorRun above{"all", {-M_PI, M_PI, -M_PI / 2, M_PI / 2, 0.0, 100.0},
                          {{Eigen::Vector3d(0.75, 0.7, 17.0), Eigen::Matrix3d::Identity()}}};
    const SceneTruth a = makeSceneTruth("a", {in_place}, {seabed}, {above}, Eigen::Vector3d::UnitX());
    const SceneTruth b =
        makeSceneTruth("b", {MeshSource{mm_y_up, where}}, {seabed}, {above}, Eigen::Vector3d::UnitX());
    const GroundTruth ga = groundTruthInGrid(a, kGrid), gb = groundTruthInGrid(b, kGrid);
    EXPECT_EQ(countSet(ga.object.solid), 5u * 4u * 3u);
    EXPECT_EQ(ga.object.solid, gb.object.solid);
    EXPECT_EQ(ga.visible, gb.visible);
}

// Bare seabed: no true object, every predicted voxel is false.
TEST(ObjectFree, MetricsAreNullButFalseVolumeAndObjectCount) {
    const std::string seabed =
        test::writeOff("free_seabed", {{-5, -5, 20.0}, {9, -5, 20.0}, {9, 9, 20.0}, {-5, 9, 20.0}}, {{0, 1, 2, 3}});
    const SensorRun above{"all", {-M_PI, M_PI, -M_PI / 2, M_PI / 2, 0.0, 100.0},
                          {{Eigen::Vector3d(1.0, 1.0, 17.0), Eigen::Matrix3d::Identity()}}};
    const SceneTruth scene = makeSceneTruth("bare", {}, {seabed}, {above}, Eigen::Vector3d::UnitX());
    EXPECT_EQ(scene.objects_true, 0);
    EXPECT_TRUE(scene.samples.empty());
    const GroundTruth gt = groundTruthInGrid(scene, kGrid);
    EXPECT_EQ(countSet(gt.object.solid), 0u);

    Prediction p;
    p.object.assign(kGrid.size(), 0);
    for (int x = 10; x < 13; ++x) p.object[kGrid.linear(x, 10, 15)] = 1;  // 3 false voxels
    p.stats.objects = 1;
    VariantScore s = scorePrediction(kGrid, p, gt, scene);
    s.variant = "fused";
    EXPECT_FALSE(s.metrics.precision.has_value());
    EXPECT_FALSE(s.metrics.recall_visible.has_value());
    EXPECT_FALSE(s.metrics.iou.has_value());
    EXPECT_FALSE(s.metrics.chamfer_cm.has_value());
    EXPECT_FALSE(s.face_angle_deg.has_value());
    ASSERT_TRUE(s.metrics.false_slope_m3.has_value());
    EXPECT_NEAR(*s.metrics.false_slope_m3, 3e-3, 1e-12);
    EXPECT_EQ(s.objects, 1);
    EXPECT_EQ(s.objects_true, 0);

    const auto j = nlohmann::json::parse(reportJson("bare", {s}));
    EXPECT_TRUE(j["variants"]["fused"]["precision"].is_null());
    EXPECT_EQ(j["variants"]["fused"]["counts"]["objects"], 1);
    EXPECT_EQ(j["variants"]["fused"]["counts"]["objects_true"], 0);
    EXPECT_NE(scoreTable({s}).find("objects_true"), std::string::npos);
}

// The visibility pass pre-tests the field of view cheaply; it must never
// drop a point SensorFov::contains accepts. Without occluders a sample is seen
// exactly when some pose holds it in its field of view.
TEST(VisibilityShortcuts, FovPretestMatchesContains) {
    const TriangleMesh box = loadMesh(test::writeBox("fov_box", {-1.0, -0.6, 19.0}, {1.0, 0.6, 20.0}));
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (const SensorFov& fov : {SensorFov::fls(FlsGeometry{}), SensorFov::ps(PsGeometry{})}) {
        SensorRun run{"s", fov, {}};
        for (int k = 0; k < 12; ++k) {  // poses >= 2.5 cm apart: none is thinned away
            // Around the box, roughly facing it, tilted and rolled a little.
            const double azimuth = M_PI * u(rng), distance = 3.5 + 1.5 * u(rng);
            const Eigen::Vector3d at(distance * std::cos(azimuth), distance * std::sin(azimuth), 17.0 + 0.5 * u(rng));
            const double yaw = azimuth + M_PI + 0.6 * u(rng);
            const Eigen::Matrix3d r = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                                       Eigen::AngleAxisd(0.3 * u(rng), Eigen::Vector3d::UnitY()) *
                                       Eigen::AngleAxisd(0.3 * u(rng), Eigen::Vector3d::UnitX()))
                                          .toRotationMatrix();
            run.poses.push_back({at, r});
        }
        const auto samples = sampleVisibleSurface({box}, {}, {run});
        std::size_t seen = 0;
        for (const SurfaceSample& s : samples) {
            bool expected = false;
            for (const SensorPose& p : run.poses)
                expected = expected || fov.contains(p.world_from_sensor.transpose() * (s.point - p.position));
            ASSERT_EQ(s.seen_by != 0, expected) << s.point.transpose();
            seen += expected;
        }
        EXPECT_GT(seen, 0u);
        EXPECT_LT(seen, samples.size());
    }
}

// The result does not depend on the number of threads.
TEST(VisibilityShortcuts, ThreadsGiveTheSameBits) {
    const TriangleMesh box = loadMesh(test::writeBox("thr_box", {-1.0, -0.6, 19.0}, {1.0, 0.6, 20.0}));
    const TriangleMesh seabed =
        loadMesh(test::writeOff("thr_seabed", {{-9, -9, 20.0}, {9, -9, 20.0}, {9, 9, 20.0}, {-9, 9, 20.0}}, {{0, 1, 2, 3}}));
    SensorRun run{"fls", SensorFov::fls(FlsGeometry{}), {}};
    for (int k = 0; k < 200; ++k) run.poses.push_back({Eigen::Vector3d(-8.0 + 0.05 * k, 0.3, 16.9), Eigen::Matrix3d::Identity()});
    VisibilityOptions one;
    one.threads = 1;
    VisibilityOptions two;
    two.threads = 2;
    const auto a = sampleVisibleSurface({box}, {box, seabed}, {run}, one);
    const auto b = sampleVisibleSurface({box}, {box, seabed}, {run}, two);
    ASSERT_EQ(a.size(), b.size());
    std::size_t seen = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        ASSERT_EQ(a[i].seen_by, b[i].seen_by) << i;
        seen += a[i].seen_by != 0;
    }
    EXPECT_GT(seen, 0u);
}

// A long, thin triangle is sampled in proportion to its area (rows along it),
// not with (length / spacing)^2 points, and still about `spacing` apart.
TEST(VisibilityShortcuts, SliverSamplesFollowArea) {
    // 3 m long, 1 cm high: a regular subdivision would take (3 m / 2.5 cm)^2 = 14400.
    const TriangleMesh sliver{{{0, 0, 0}, {3.0, 0, 0}, {1.5, 0.01, 0}}, {{0, 1, 2}}};
    const auto samples = sampleVisibleSurface({sliver}, {}, {});
    // One row (height 1 cm < 2.5 cm) at mid-height, 1.5 m long: 60 points 2.5 cm apart.
    EXPECT_EQ(samples.size(), 60u);
    for (const SurfaceSample& s : samples) {  // strictly inside
        EXPECT_GT(s.point.y(), 0.0);
        EXPECT_LT(s.point.y(), 0.01 * std::min(s.point.x(), 3.0 - s.point.x()) / 1.5);
    }
    // A well-shaped triangle keeps the regular subdivision: n = ceil(0.1414 / 0.025) = 6, 36 centroids.
    const TriangleMesh fat{{{0, 0, 0}, {0.1, 0, 0}, {0, 0.1, 0}}, {{0, 1, 2}}};
    EXPECT_EQ(sampleVisibleSurface({fat}, {}, {}).size(), 36u);
}

}  // namespace
}  // namespace sonarfusion::eval
