// Metrics on hand-derivable maps. Truth G: the 2.0 x 1.2 x 1.0 m box, grid
// aligned, i.e. 20 x 12 x 10 voxels (2400); its surface S = 2400 - 18*10*8 =
// 960 voxels, used as the visible set V.
//
// Prediction = G shifted +3 voxels along x (slabs x0+3 .. x0+22; one slab = 120):
//  - correct: slabs up to x0+20 (face neighbour of G's last slab x0+19):
//    18 of 20 slabs -> precision 0.9; false slope 2 slabs = 240 voxels = 0.24 m^3.
//  - recalled: S voxels at x >= x0+2 (then a predicted voxel is 1 voxel away);
//    lost: slab x0 (120, the full end face) and the ring of x0+1 (12*10 - 10*8 = 40):
//    recall = 800/960.
//  - IoU = 17 slabs / 23 slabs.
//  - Chamfer pred->gt: slabs x0+20, 21, 22 are 1, 2, 3 voxels out:
//    120*(1+2+3)*10 cm / 2400 = 3 cm. gt->pred: slab x0 (120) at 3 voxels,
//    x0+1 ring (40) at 2, x0+2 ring (40) at 1: (360+80+40)*10 cm / 960 = 5 cm;
//    mean 4 cm.
#include <gtest/gtest.h>

#include <random>

#include "distance_transform.hpp"
#include "eval_test_helpers.hpp"
#include "metrics.hpp"
#include "voxelise.hpp"

namespace sonarfusion::eval {
namespace {

class BoxMetrics : public ::testing::Test {
protected:
    void SetUp() override {
        grid_ = GridSpec{Eigen::Vector3d(0, 0, 18.0), 0.1, 40, 30, 30};
        // Box x [1.0, 3.0], y [1.0, 2.2], z [19.0, 20.0] -> cells x 10..29.
        const auto path = test::writeBox("metrics_box", {1.0, 1.0, 19.0}, {3.0, 2.2, 20.0});
        truth_ = voxeliseMesh(loadMesh(path), grid_);
    }
    VoxelMask shifted(const VoxelMask& m, int dx) const {
        VoxelMask out(m.size(), 0);
        for (std::size_t i = 0; i < m.size(); ++i) {
            if (!m[i]) continue;
            const Eigen::Vector3i v = grid_.index(i);
            if (grid_.contains(v.x() + dx, v.y(), v.z())) out[grid_.linear(v.x() + dx, v.y(), v.z())] = 1;
        }
        return out;
    }
    GridSpec grid_;
    MeshVoxels truth_;
};

TEST_F(BoxMetrics, TruthHasHandCounts) {
    EXPECT_EQ(countSet(truth_.solid), 2400u);
    EXPECT_EQ(countSet(truth_.surface), 960u);
}

TEST_F(BoxMetrics, PerfectMapIsPerfect) {
    const Metrics m = computeMetrics(grid_, truth_.solid, truth_.solid, truth_.surface);
    EXPECT_DOUBLE_EQ(*m.precision, 1.0);
    EXPECT_DOUBLE_EQ(*m.recall_visible, 1.0);
    EXPECT_DOUBLE_EQ(*m.iou, 1.0);
    EXPECT_DOUBLE_EQ(*m.chamfer_cm, 0.0);
    EXPECT_DOUBLE_EQ(*m.false_slope_m3, 0.0);
}

TEST_F(BoxMetrics, ShiftedThreeVoxelsDegradesByDerivedAmounts) {
    const Metrics m = computeMetrics(grid_, shifted(truth_.solid, 3), truth_.solid, truth_.surface);
    EXPECT_EQ(m.counts.predicted, 2400u);
    EXPECT_NEAR(*m.precision, 0.9, 1e-12);
    EXPECT_NEAR(*m.recall_visible, 800.0 / 960.0, 1e-12);
    EXPECT_NEAR(*m.iou, 17.0 / 23.0, 1e-12);
    EXPECT_NEAR(*m.chamfer_pred_to_gt_cm, 3.0, 1e-9);
    EXPECT_NEAR(*m.chamfer_gt_to_pred_cm, 5.0, 1e-9);
    EXPECT_NEAR(*m.chamfer_cm, 4.0, 1e-9);
    EXPECT_NEAR(*m.false_slope_m3, 0.24, 1e-12);
}

// A prediction of only the surface shell (what a sonar map looks like), shifted
// 3 voxels: shell slabs x0+3..x0+22 are end faces at x0+3 and x0+22 (120 each)
// and 40-voxel rings between. Incorrect: ring x0+21 (2 out) and face x0+22
// (3 out) = 160 of 960 -> precision 800/960, false slope 0.16 m^3.
TEST_F(BoxMetrics, ShiftedShellPrecision) {
    const Metrics m = computeMetrics(grid_, shifted(truth_.surface, 3), truth_.solid, truth_.surface);
    EXPECT_NEAR(*m.precision, 800.0 / 960.0, 1e-12);
    EXPECT_NEAR(*m.false_slope_m3, 0.16, 1e-12);
}

TEST_F(BoxMetrics, EmptyPredictionHasNullPrecisionAndZeroRecall) {
    const Metrics m = computeMetrics(grid_, VoxelMask(grid_.size(), 0), truth_.solid, truth_.surface);
    EXPECT_FALSE(m.precision.has_value());
    EXPECT_FALSE(m.chamfer_cm.has_value());
    EXPECT_FALSE(m.false_slope_m3.has_value());
    EXPECT_DOUBLE_EQ(*m.recall_visible, 0.0);
    EXPECT_DOUBLE_EQ(*m.iou, 0.0);
}

TEST(DistanceTransform, MatchesBruteForce) {
    const GridSpec g{Eigen::Vector3d::Zero(), 0.1, 13, 9, 7};
    std::mt19937 rng(7);
    std::bernoulli_distribution pick(0.02);
    VoxelMask mask(g.size(), 0);
    for (auto& v : mask) v = pick(rng);
    mask[5] = 1;
    const std::vector<double> d = squaredDistanceToSet(g, mask);
    for (std::size_t i = 0; i < g.size(); ++i) {
        const Eigen::Vector3i a = g.index(i);
        double best = std::numeric_limits<double>::infinity();
        for (std::size_t j = 0; j < g.size(); ++j)
            if (mask[j]) best = std::min(best, static_cast<double>((g.index(j) - a).squaredNorm()));
        ASSERT_DOUBLE_EQ(d[i], best) << "voxel " << i;
    }
}

TEST(DistanceTransform, EmptyMaskIsInfinite) {
    const GridSpec g{Eigen::Vector3d::Zero(), 0.1, 4, 4, 4};
    for (double d : squaredDistanceToSet(g, VoxelMask(g.size(), 0))) EXPECT_TRUE(std::isinf(d));
}

}  // namespace
}  // namespace sonarfusion::eval
