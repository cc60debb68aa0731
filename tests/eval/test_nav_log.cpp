// sf-eval --log: NAV and NAV_TRUTH samples read from an LCM log with the
// project's reader; other channels skipped, undecodable events counted.
#include <gtest/gtest.h>

#include <sonarfusion/nav_state_t.hpp>

#include <filesystem>
#include <lcm/lcm-cpp.hpp>
#include <vector>

#include <unistd.h>

#include "nav_log.hpp"

namespace sonarfusion::eval {
namespace {

void writeEvent(lcm::LogFile& log, int64_t& eventnum, const std::string& channel, std::vector<uint8_t> bytes) {
    lcm::LogEvent ev;
    ev.eventnum = eventnum++;
    ev.timestamp = 0;
    ev.channel = channel;
    ev.datalen = static_cast<int32_t>(bytes.size());
    ev.data = bytes.data();
    ASSERT_EQ(log.writeEvent(&ev), 0);
}

std::vector<uint8_t> navBytes(int64_t utime, double x, double yaw) {
    nav_state_t m{};
    m.utime = utime;
    m.position_ned[0] = x;
    m.position_ned[2] = 17.0;
    m.rpy[2] = yaw;
    std::vector<uint8_t> b(static_cast<std::size_t>(m.getEncodedSize()));
    m.encode(b.data(), 0, static_cast<int>(b.size()));
    return b;
}

TEST(NavLog, ReadsNavAndTruthFromALog) {
    const std::string path =
        (std::filesystem::temp_directory_path() / ("sf_eval_navlog." + std::to_string(::getpid()) + ".lcmlog")).string();
    {
        lcm::LogFile log(path, "w");
        ASSERT_TRUE(log.good());
        int64_t n = 0;
        for (int64_t k = 0; k < 5; ++k) {
            writeEvent(log, n, "NAV", navBytes(1000 * k, 0.1 * k + 0.02, 0.01));
            writeEvent(log, n, "TRUTH", navBytes(1000 * k, 0.1 * k, 0.0));
            writeEvent(log, n, "PS", std::vector<uint8_t>(300, 7));
        }
        writeEvent(log, n, "NAV", {1, 2, 3});  // not a nav_state_t
    }
    const NavLog log = readNavLog(path, "NAV", "TRUTH", 1 << 16);
    std::filesystem::remove(path);
    ASSERT_EQ(log.nav.size(), 5u);
    ASSERT_EQ(log.truth.size(), 5u);
    EXPECT_EQ(log.undecodable, 1);
    EXPECT_FALSE(log.lost_data);
    EXPECT_EQ(log.nav[3].utime, 3000);
    EXPECT_DOUBLE_EQ(log.nav[3].position.x(), 0.32);
    EXPECT_DOUBLE_EQ(log.nav[3].position.z(), 17.0);
    EXPECT_DOUBLE_EQ(log.nav[3].yaw, 0.01);
    const auto s = compareNavigation(log.nav, log.truth);
    ASSERT_TRUE(s);
    EXPECT_EQ(s->samples, 5);
    EXPECT_NEAR(s->position_rms_m, 0.02, 1e-12);
    EXPECT_NEAR(s->heading_rms_deg, 0.01 * 180.0 / M_PI, 1e-9);
    EXPECT_THROW((void)readNavLog(path + ".missing", "NAV", "TRUTH", 1 << 16), std::runtime_error);
}

}  // namespace
}  // namespace sonarfusion::eval
