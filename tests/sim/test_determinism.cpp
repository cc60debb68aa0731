// Same seed -> same bytes; different seed -> same geometry and time stamps,
// different noise. Whole logs, written through the real log writer.
#include <gtest/gtest.h>

#include <lcm/lcm-cpp.hpp>

#include "lcm_output.hpp"
#include "sim_test_util.hpp"
#include "simulator.hpp"

namespace sonarfusion::sim {
namespace {

using test::TempDir;
using test::TinyScenario;
using Event = test::LogEvent;
using test::readLog;

template <class Message>
Message decode(const Event& e) {
    Message m;
    EXPECT_EQ(m.decode(e.data.data(), 0, static_cast<int>(e.data.size())), static_cast<int>(e.data.size()));
    return m;
}

class DeterminismTest : public ::testing::Test {
protected:
    void SetUp() override {
        saveObj(test::flatPlane(20.0), dir.file("plane.obj"));
        saveObj(test::box(4.0, 0.5, 19.5, 0.5, 0.5, 0.5), dir.file("box.obj"));
    }
    Scenario scenario(uint64_t seed) {
        TinyScenario t;
        t.meshes = "- {file: plane.obj, role: seabed}\n- {file: box.obj, role: object}\n";
        t.sequences = 12;
        t.noise = "{speckle: true, floor: 10}";
        t.extra = "seed: " + std::to_string(seed) + "\nfls: {rays_elevation: 64}\n";
        return loadScenarioFromString(t.yaml(), dir.path());
    }
    std::string simulate(uint64_t seed, int threads, const std::string& name) {
        return test::simulateToLog(scenario(seed), dir.file(name), threads);
    }
    TempDir dir;
};

TEST_F(DeterminismTest, SameSeedGivesIdenticalLogsWhateverTheThreadCount) {
    const std::string a = test::readBytes(simulate(7, 1, "a.lcmlog"));
    const std::string b = test::readBytes(simulate(7, 2, "b.lcmlog"));
    ASSERT_GT(a.size(), 10000u);
    EXPECT_TRUE(a == b) << "logs of the same seed differ";
}

TEST_F(DeterminismTest, DifferentSeedChangesOnlyTheNoise) {
    const auto a = readLog(simulate(7, 2, "a.lcmlog"));
    const auto b = readLog(simulate(8, 2, "b.lcmlog"));
    ASSERT_EQ(a.size(), b.size());
    ASSERT_EQ(a.size(), 12u + 12u + 3u);  // NAV + PS every sequence, FLS every 4th
    int fls_differs = 0, ps_differs = 0;
    int64_t last_utime = -1;
    for (std::size_t i = 0; i < a.size(); ++i) {
        ASSERT_EQ(a[i].channel, b[i].channel) << i;
        ASSERT_EQ(a[i].timestamp, b[i].timestamp) << i;
        if (a[i].channel == "NAV") {
            EXPECT_EQ(a[i].data, b[i].data) << "NAV carries no noise";
            const auto nav = decode<nav_state_t>(a[i]);
            EXPECT_GT(nav.utime, last_utime);  // strictly increasing, NAV first in its sequence
            last_utime = nav.utime;
        } else if (a[i].channel == "FLS") {
            auto fa = decode<fls_image_t>(a[i]), fb = decode<fls_image_t>(b[i]);
            EXPECT_EQ(fa.utime, last_utime);
            EXPECT_EQ(fa.seq, fb.seq);
            EXPECT_EQ(fa.beam_bearing, fb.beam_bearing);
            EXPECT_EQ(fa.row_range, fb.row_range);
            fls_differs += fa.data != fb.data;
            fa.data = fb.data;  // apart from the pixels, the messages are identical
            EXPECT_EQ(encodeMessage(fa), encodeMessage(fb));
        } else {
            ASSERT_EQ(a[i].channel, "PS");
            auto pa = decode<ps_ping_t>(a[i]), pb = decode<ps_ping_t>(b[i]);
            EXPECT_EQ(pa.utime, last_utime);
            ps_differs += pa.intensity != pb.intensity;
            pa.intensity = pb.intensity;
            EXPECT_EQ(encodeMessage(pa), encodeMessage(pb));
        }
    }
    EXPECT_EQ(fls_differs, 3);
    EXPECT_EQ(ps_differs, 12);
}

TEST_F(DeterminismTest, LivePublishingSendsTheLogsBytes) {
    const auto logged = readLog(simulate(7, 2, "a.lcmlog"));
    lcm::LCM lcm("memq://");
    ASSERT_TRUE(lcm.good());
    std::vector<Event> received;
    struct Recorder {
        std::vector<Event>* out;
        void handle(const lcm::ReceiveBuffer* rbuf, const std::string& channel) {
            out->push_back({channel, 0, std::string(static_cast<const char*>(rbuf->data), rbuf->data_size)});
        }
    } recorder{&received};
    lcm.subscribe(".*", &Recorder::handle, &recorder);
    const Scenario s = scenario(7);
    const Simulator sim(s);
    LivePublisher live(lcm, 0.0);
    sim.run(1, -1, [&](const SequenceOutput& out) {
        writeSequence(live, s.channels, out);
        while (lcm.handleTimeout(0) > 0) {
        }
    });
    ASSERT_EQ(received.size(), logged.size());
    for (std::size_t i = 0; i < logged.size(); ++i) {
        EXPECT_EQ(received[i].channel, logged[i].channel);
        EXPECT_TRUE(received[i].data == logged[i].data) << "message " << i;
    }
    EXPECT_EQ(live.failures(), 0);
}

TEST_F(DeterminismTest, SpeckleFollowsThePoseWhenAsked) {
    // A vehicle holding still: FLS frames 0 and 4 see the same scene.
    auto frames = [&](bool follows_pose) {
        TinyScenario t;
        t.meshes = "- {file: plane.obj, role: seabed}\n- {file: box.obj, role: object}\n";
        t.step = 0.0;
        t.sequences = 5;
        t.noise = std::string("{speckle: true, floor: 10, follows_pose: ") + (follows_pose ? "true" : "false") + "}";
        t.extra = "seed: 3\nfls: {rays_elevation: 64}\n";
        const Simulator sim(loadScenarioFromString(t.yaml(), dir.path()));
        std::vector<std::vector<uint8_t>> out;
        sim.run(1, -1, [&](const SequenceOutput& o) {
            if (o.has_fls) out.push_back(o.fls.data);
        });
        return out;
    };
    const auto still = frames(true);
    ASSERT_EQ(still.size(), 2u);
    EXPECT_EQ(still[0], still[1]);  // same pose, same speckle
    const auto redrawn = frames(false);
    ASSERT_EQ(redrawn.size(), 2u);
    EXPECT_NE(redrawn[0], redrawn[1]);  // default: fresh speckle every ping
}

TEST_F(DeterminismTest, SequenceCountersPerChannel) {
    const auto events = readLog(simulate(7, 2, "a.lcmlog"));
    int64_t nav = 0, ps = 0, fls = 0;
    for (const Event& e : events) {
        if (e.channel == "NAV") {
            EXPECT_EQ(decode<nav_state_t>(e).seq, nav++);
        } else if (e.channel == "PS") {
            EXPECT_EQ(decode<ps_ping_t>(e).seq, ps++);
        } else {
            EXPECT_EQ(decode<fls_image_t>(e).seq, fls++);
        }
    }
    EXPECT_EQ(fls, 3);
}

}  // namespace
}  // namespace sonarfusion::sim
