#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "sonarfusion/state_codec.hpp"
#include "sonarfusion/voxel_map.hpp"

using namespace sonarfusion;

TEST(VoxelMap, DefaultIsPaperGrid) {
    VoxelMap m{MapConfig{}};
    EXPECT_EQ(m.nx(), 100);
    EXPECT_EQ(m.ny(), 100);
    EXPECT_EQ(m.nz(), 100);
    EXPECT_EQ(m.size(), 1000000u);
    EXPECT_DOUBLE_EQ(m.resolution(), 0.1);
    EXPECT_FALSE(m.initialised());
}

TEST(VoxelMap, InitialiseCentresTheGridOnThePoint) {
    VoxelMap m{MapConfig{}};
    m.initialiseAt(Eigen::Vector3d(1.0, -2.0, 20.0));
    EXPECT_TRUE(m.initialised());
    EXPECT_TRUE(m.origin().isApprox(Eigen::Vector3d(-4.0, -7.0, 15.0)));
    EXPECT_TRUE(m.centre().isApprox(Eigen::Vector3d(1.0, -2.0, 20.0)));
}

TEST(VoxelMap, AnchorSnapsToTheWorldLattice) {
    // Two detections 4 cm apart give the same voxels (issue 9: results moved with the anchor).
    VoxelMap a{MapConfig{}}, b{MapConfig{}};
    a.initialiseAt(Eigen::Vector3d(1.03, -2.01, 20.04));
    b.initialiseAt(Eigen::Vector3d(0.99, -1.98, 20.0));
    EXPECT_TRUE(a.origin().isApprox(Eigen::Vector3d(-4.0, -7.0, 15.0)));
    EXPECT_TRUE(a.origin().isApprox(b.origin()));
    MapConfig exact;
    exact.snap_to_world_lattice = false;
    VoxelMap c{exact};
    c.initialiseAt(Eigen::Vector3d(1.03, -2.01, 20.04));
    EXPECT_TRUE(c.centre().isApprox(Eigen::Vector3d(1.03, -2.01, 20.04)));
}

TEST(VoxelMap, WorldToIndexFloorsAndRejectsOutside) {
    VoxelMap m{MapConfig{}};
    m.initialiseAt(Eigen::Vector3d(5.0, 5.0, 5.0));  // origin at 0,0,0
    VoxelIndex v;
    ASSERT_TRUE(m.worldToIndex(Eigen::Vector3d(0.05, 0.15, 9.99), v));
    EXPECT_EQ(v, (VoxelIndex{0, 1, 99}));
    // Just below zero must NOT fold into voxel 0 (int truncation would).
    EXPECT_FALSE(m.worldToIndex(Eigen::Vector3d(-0.01, 0.5, 0.5), v));
    EXPECT_FALSE(m.worldToIndex(Eigen::Vector3d(10.0, 0.5, 0.5), v));
    EXPECT_FALSE(m.worldToIndex(Eigen::Vector3d(std::nan(""), 0.5, 0.5), v));
    EXPECT_FALSE(m.worldToIndex(Eigen::Vector3d(1e300, 0.5, 0.5), v));
}

TEST(VoxelMap, LinearIndexRoundTrips) {
    VoxelMap m{MapConfig{}};
    const VoxelIndex v{7, 42, 93};
    EXPECT_EQ(m.linear(v), (93u * 100 + 42) * 100 + 7);
    EXPECT_EQ(m.fromLinear(m.linear(v)), v);
    m.initialiseAt(Eigen::Vector3d::Zero());
    VoxelIndex back;
    ASSERT_TRUE(m.worldToIndex(m.centreOf(v), back));
    EXPECT_EQ(back, v);
}

TEST(VoxelMap, ClampsAtPlusMinusFive) {
    VoxelMap m{MapConfig{}};
    for (int i = 0; i < 100; ++i) m.add(3, 0.4f);
    EXPECT_FLOAT_EQ(m.logOdds(3), 5.0f);
    for (int i = 0; i < 100; ++i) m.add(3, -0.7f);
    EXPECT_FLOAT_EQ(m.logOdds(3), -5.0f);
    m.add(3, 0.5f);  // climbs back from the clamp at once
    EXPECT_FLOAT_EQ(m.logOdds(3), -4.5f);
    EXPECT_NEAR(m.occupancy(3), 1.0 / (1.0 + std::exp(4.5)), 1e-6);
}

// The clamp is written min(hi, max(lo, x)) so it compiles to maxss/minss with
// no register copies (docs/performance.md, "The clamp without register
// copies"); its other effect: a NaN increment, which the Mapper's input checks
// should never let through, lands on the lower bound instead of leaving a NaN
// that no later update could clear. The same through the hot loops' Writer.
TEST(VoxelMap, ANonFiniteIncrementCannotLeaveANaNInTheMap) {
    VoxelMap m{MapConfig{}};
    m.add(3, 1.0f);
    m.add(3, std::nanf(""));
    ASSERT_TRUE(std::isfinite(m.logOdds(3)));
    EXPECT_FLOAT_EQ(m.logOdds(3), m.clampMin());
    m.add(3, 0.5f);  // and it takes updates again
    EXPECT_FLOAT_EQ(m.logOdds(3), m.clampMin() + 0.5f);
    VoxelMap::Writer w = m.writer();
    w.add(4, std::nanf(""));
    ASSERT_TRUE(std::isfinite(m.logOdds(4)));
    EXPECT_FLOAT_EQ(m.logOdds(4), m.clampMin());
    w.add(5, std::numeric_limits<float>::infinity());
    EXPECT_FLOAT_EQ(m.logOdds(5), m.clampMax());
}

// The flags live in three byte planes (PS observed, FLS touched, echo count);
// flags() must still give the saved byte, and the checkpoint keep its format.
TEST(VoxelMap, TheFlagByteSurvivesItsPlanes) {
    MapConfig c;
    c.nx = c.ny = c.nz = 8;  // 512 voxels: two of each byte value
    VoxelMap m{c};
    m.initialiseAt(Eigen::Vector3d::Zero());
    for (std::size_t i = 0; i < m.size(); ++i) m.setFlags(i, static_cast<uint8_t>(i));
    for (std::size_t i = 0; i < m.size(); ++i) {
        const auto f = static_cast<uint8_t>(i);
        ASSERT_EQ(m.flags(i), f);
        EXPECT_EQ(m.psObserved(i), (f & VoxelMap::kPsObserved) != 0);
        EXPECT_EQ(m.flsTouched(i), (f & VoxelMap::kFlsTouched) != 0);
        EXPECT_EQ(m.psEchoCount(i), f >> VoxelMap::kPsEchoShift);
    }
    // Setting a flag, through the map or a writer, leaves the other bits.
    m.setFlags(7, static_cast<uint8_t>(5u << VoxelMap::kPsEchoShift));
    m.setFlag(7, VoxelMap::kFlsTouched);
    EXPECT_EQ(m.flags(7), (5u << VoxelMap::kPsEchoShift) | VoxelMap::kFlsTouched);
    VoxelMap::Writer w = m.writer();
    w.setFlag(7, VoxelMap::kPsObserved);
    w.setFlag(7, 0);
    EXPECT_EQ(m.flags(7), (5u << VoxelMap::kPsEchoShift) | VoxelMap::kFlsTouched | VoxelMap::kPsObserved);
    // The echo count saturates and keeps the flags.
    for (int k = 0; k < 100; ++k) m.addPsEcho(7);
    EXPECT_EQ(m.psEchoCount(7), VoxelMap::kPsEchoMax);
    EXPECT_EQ(m.flags(7), 0xff);
    // A checkpoint round trip keeps every byte.
    std::vector<uint8_t> buf(m.size() * 16 + 256);
    StateWriter sw(buf.data(), buf.size());
    m.saveState(sw);
    ASSERT_FALSE(sw.overflow());
    VoxelMap back{c};
    StateReader sr(buf.data(), sw.size());
    ASSERT_TRUE(back.loadState(sr));
    for (std::size_t i = 0; i < m.size(); ++i) ASSERT_EQ(back.flags(i), m.flags(i)) << i;
}

TEST(VoxelMap, ReanchorClearsWithoutReallocating) {
    VoxelMap m{MapConfig{}};
    m.initialiseAt(Eigen::Vector3d::Zero());
    const float* before = m.logOddsData().data();
    m.add(10, 2.0f);
    m.setFlag(10, VoxelMap::kPsObserved);
    m.initialiseAt(Eigen::Vector3d(100.0, 0.0, 0.0));
    EXPECT_EQ(m.logOddsData().data(), before);
    EXPECT_FLOAT_EQ(m.logOdds(10), 0.0f);
    EXPECT_FALSE(m.psObserved(10));
    EXPECT_TRUE(m.centre().isApprox(Eigen::Vector3d(100.0, 0.0, 0.0)));
}

TEST(VoxelMap, RejectsImpossibleConfig) {
    MapConfig c;
    c.nx = 0;
    EXPECT_THROW(VoxelMap{c}, std::invalid_argument);
    c = MapConfig{};
    c.resolution = -0.1;
    EXPECT_THROW(VoxelMap{c}, std::invalid_argument);
    c = MapConfig{};
    c.clamp_min = 1.0f;
    EXPECT_THROW(VoxelMap{c}, std::invalid_argument);
}
