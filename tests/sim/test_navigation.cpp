// Issue 11: NAV errors and vehicle motion (docs/navigation.md). The scenario
// keys and their errors, the error model's statistics, latency, the motion,
// and what the simulator publishes (NAV, NAV_TRUTH, sonars from the truth).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <lcm/lcm-cpp.hpp>

#include "lcm_output.hpp"
#include "navigation.hpp"
#include "sim_test_util.hpp"
#include "simulator.hpp"
#include "trajectory.hpp"

namespace sonarfusion::sim {
namespace {

using test::readLog;
using test::TempDir;
using test::TinyScenario;

nav_state_t decodeNav(const std::string& bytes) {
    nav_state_t m{};
    EXPECT_EQ(m.decode(bytes.data(), 0, static_cast<int>(bytes.size())), static_cast<int>(bytes.size()));
    return m;
}

double wrap(double a) { return std::remainder(a, 2.0 * M_PI); }

class NavigationTest : public ::testing::Test {
protected:
    void SetUp() override {
        saveObj(test::flatPlane(20.0), dir.file("plane.obj"));
        saveObj(test::box(4.0, 0.5, 19.5, 0.5, 0.5, 0.5), dir.file("box.obj"));
    }
    // A straight pass north; `blocks` is appended top-level YAML (navigation:, motion:, ...).
    std::string yaml(const std::string& blocks, int sequences = 12, double step = 0.01, uint64_t seed = 7) const {
        TinyScenario t;
        t.meshes = "- {file: plane.obj, role: seabed}\n- {file: box.obj, role: object}\n";
        t.sequences = sequences;
        t.step = step;
        t.noise = "{speckle: true, floor: 10}";
        t.extra = "seed: " + std::to_string(seed) + "\nfls: {rays_elevation: 64}\n" + blocks;
        return t.yaml();
    }
    Scenario load(const std::string& text) { return loadScenarioFromString(text, dir.path()); }
    std::string errorField(const std::string& blocks) {
        try {
            (void)load(yaml(blocks));
        } catch (const ScenarioError& e) {
            EXPECT_NE(std::string(e.what()).find(e.field()), std::string::npos) << e.what();
            return e.field();
        }
        ADD_FAILURE() << "scenario loaded although it is bad:\n" << blocks;
        return "";
    }
    std::string simulateToLog(const std::string& text, const std::string& name, int threads = 1) {
        return test::simulateToLog(load(text), dir.file(name), threads);
    }
    TempDir dir;
};

const char* kIssueBlocks =
    "navigation: {position_noise: 0.02, depth_noise: 0.01, drift_fraction: 0.005, heading_bias_deg: 0.5,\n"
    "             heading_noise_deg: 0.2, attitude_noise_deg: 0.1, latency: 0.0}\n"
    "motion: {roll_amplitude_deg: 3.0, pitch_amplitude_deg: 2.0, yaw_amplitude_deg: 1.0, heave_amplitude: 0.05,\n"
    "         period: 6.0}\n";

TEST_F(NavigationTest, KeysLoadAndDefaultToZero) {
    const Scenario none = load(yaml(""));
    EXPECT_FALSE(none.navigation.enabled());
    EXPECT_FALSE(none.motion.enabled());
    EXPECT_FALSE(none.publishesTruth());
    EXPECT_EQ(none.channels.nav_truth, "NAV_TRUTH");

    const Scenario s = load(yaml(kIssueBlocks));
    EXPECT_DOUBLE_EQ(s.navigation.position_noise, 0.02);
    EXPECT_DOUBLE_EQ(s.navigation.depth_noise, 0.01);
    EXPECT_DOUBLE_EQ(s.navigation.drift_fraction, 0.005);
    EXPECT_NEAR(s.navigation.heading_bias, 0.5 * kDegToRad, 1e-15);
    EXPECT_NEAR(s.navigation.heading_noise, 0.2 * kDegToRad, 1e-15);
    EXPECT_NEAR(s.navigation.attitude_noise, 0.1 * kDegToRad, 1e-15);
    EXPECT_DOUBLE_EQ(s.navigation.latency, 0.0);
    EXPECT_NEAR(s.motion.roll_amplitude, 3.0 * kDegToRad, 1e-15);
    EXPECT_NEAR(s.motion.pitch_amplitude, 2.0 * kDegToRad, 1e-15);
    EXPECT_NEAR(s.motion.yaw_amplitude, 1.0 * kDegToRad, 1e-15);
    EXPECT_DOUBLE_EQ(s.motion.heave_amplitude, 0.05);
    EXPECT_DOUBLE_EQ(s.motion.period, 6.0);
    EXPECT_TRUE(s.publishesTruth());
    EXPECT_EQ(load(yaml(std::string(kIssueBlocks) + "channels: {nav_truth: GT}\n")).channels.nav_truth, "GT");
    // A heading bias may be negative; a zero period is fine while the motion is off.
    EXPECT_NEAR(load(yaml("navigation: {heading_bias_deg: -1}\nmotion: {period: 0}\n")).navigation.heading_bias,
                -kDegToRad, 1e-15);
}

TEST_F(NavigationTest, BadValuesNameTheField) {
    EXPECT_EQ(errorField("navigation: {position_noise: -0.1}\n"), "navigation.position_noise");
    EXPECT_EQ(errorField("navigation: {depth_noise: .nan}\n"), "navigation.depth_noise");
    EXPECT_EQ(errorField("navigation: {drift_fraction: -0.005}\n"), "navigation.drift_fraction");
    EXPECT_EQ(errorField("navigation: {heading_bias_deg: .nan}\n"), "navigation.heading_bias_deg");
    EXPECT_EQ(errorField("navigation: {heading_noise_deg: -1}\n"), "navigation.heading_noise_deg");
    EXPECT_EQ(errorField("navigation: {attitude_noise_deg: .inf}\n"), "navigation.attitude_noise_deg");
    EXPECT_EQ(errorField("navigation: {latency: -0.01}\n"), "navigation.latency");
    EXPECT_EQ(errorField("navigation: {latency: soon}\n"), "navigation.latency");
    EXPECT_EQ(errorField("navigation: {position_nosie: 0.1}\n"), "navigation.position_nosie");
    EXPECT_EQ(errorField("motion: {roll_amplitude_deg: 3}\n"), "motion.period");  // amplitude without a period
    EXPECT_EQ(errorField("motion: {heave_amplitude: 0.05, period: 0}\n"), "motion.period");
    EXPECT_EQ(errorField("motion: {pitch_amplitude_deg: 2, period: -6}\n"), "motion.period");
    EXPECT_EQ(errorField("motion: {roll_amplitude_deg: -3, period: 6}\n"), "motion.roll_amplitude_deg");
    EXPECT_EQ(errorField("motion: {yaw_amplitude_deg: .nan, period: 6}\n"), "motion.yaw_amplitude_deg");
    EXPECT_EQ(errorField("motion: {period: .nan}\n"), "motion.period");
    EXPECT_EQ(errorField("motion: {surge: 1}\n"), "motion.surge");
    EXPECT_EQ(errorField(std::string(kIssueBlocks) + "channels: {nav_truth: NAV}\n"), "channels.nav_truth");
}

TEST_F(NavigationTest, ZeroBlocksGiveTheLogOfAScenarioWithoutThem) {
    const std::string zero =
        "navigation: {position_noise: 0, depth_noise: 0, drift_fraction: 0, heading_bias_deg: 0,\n"
        "             heading_noise_deg: 0, attitude_noise_deg: 0, latency: 0}\n"
        "motion: {roll_amplitude_deg: 0, pitch_amplitude_deg: 0, yaw_amplitude_deg: 0, heave_amplitude: 0, "
        "period: 6}\n";
    const std::string a = test::readBytes(simulateToLog(yaml(""), "none.lcmlog"));
    const std::string b = test::readBytes(simulateToLog(yaml(zero), "zero.lcmlog", 2));
    ASSERT_GT(a.size(), 10000u);
    EXPECT_TRUE(a == b) << "all-zero navigation/motion blocks changed the log";
    for (const test::LogEvent& e : readLog(dir.file("zero.lcmlog"))) EXPECT_NE(e.channel, "NAV_TRUTH");
}

TEST_F(NavigationTest, NavErrorsChangeNavOnlyAndTheTruthIsPublished) {
    // NAV errors without motion: the sonars see exactly what they saw before
    // (same true pose, speckle streams untouched), NAV differs, and NAV_TRUTH
    // carries the NAV of the error-free run byte for byte.
    const auto clean = readLog(simulateToLog(yaml(""), "clean.lcmlog"));
    const auto noisy = readLog(simulateToLog(
        yaml("navigation: {position_noise: 0.02, drift_fraction: 0.01, heading_bias_deg: 0.5, heading_noise_deg: 0.2,"
             " attitude_noise_deg: 0.1, depth_noise: 0.01}\n"),
        "noisy.lcmlog"));
    std::vector<test::LogEvent> clean_nav, clean_sonar, noisy_nav, noisy_truth, noisy_sonar;
    for (const test::LogEvent& e : clean) (e.channel == "NAV" ? clean_nav : clean_sonar).push_back(e);
    std::vector<std::string> order;
    for (const test::LogEvent& e : noisy) {
        if (order.size() < 4) order.push_back(e.channel);
        if (e.channel == "NAV") noisy_nav.push_back(e);
        else if (e.channel == "NAV_TRUTH") noisy_truth.push_back(e);
        else noisy_sonar.push_back(e);
    }
    EXPECT_EQ(order, (std::vector<std::string>{"NAV", "NAV_TRUTH", "PS", "FLS"}));  // sequence 0
    ASSERT_EQ(noisy_truth.size(), clean_nav.size());
    ASSERT_EQ(noisy_nav.size(), clean_nav.size());
    ASSERT_EQ(noisy_sonar.size(), clean_sonar.size());
    for (std::size_t i = 0; i < clean_sonar.size(); ++i) {
        EXPECT_EQ(noisy_sonar[i].channel, clean_sonar[i].channel);
        EXPECT_TRUE(noisy_sonar[i].data == clean_sonar[i].data) << "sonar message " << i << " changed";
    }
    int differs = 0;
    for (std::size_t i = 0; i < clean_nav.size(); ++i) {
        EXPECT_TRUE(noisy_truth[i].data == clean_nav[i].data) << "NAV_TRUTH " << i;
        const nav_state_t n = decodeNav(noisy_nav[i].data), t = decodeNav(noisy_truth[i].data);
        EXPECT_EQ(n.utime, t.utime);
        EXPECT_EQ(n.seq, t.seq);
        EXPECT_EQ(n.altitude, t.altitude);  // from the true pose (no latency here)
        differs += n.position_ned[0] != t.position_ned[0];
        EXPECT_LT(std::fabs(wrap(n.rpy[2] - t.rpy[2] - 0.5 * kDegToRad)), 5 * 0.2 * kDegToRad);
    }
    EXPECT_EQ(differs, static_cast<int>(clean_nav.size()));
}

TEST_F(NavigationTest, NavErrorStatistics) {
    // 4000 sequences, no drift: white noise of the given rms, the heading bias as the mean.
    const Scenario s = load(yaml(
        "navigation: {position_noise: 0.02, depth_noise: 0.01, heading_bias_deg: 0.5, heading_noise_deg: 0.2,"
        " attitude_noise_deg: 0.1}\n",
        4000));
    const auto seqs = buildSequences(s);
    const auto nav = reportNavigation(s, seqs);
    ASSERT_EQ(nav.size(), seqs.size());
    double sx = 0, sxx = 0, syy = 0, szz = 0, sh = 0, shh = 0, srr = 0, spp = 0;
    for (std::size_t i = 0; i < seqs.size(); ++i) {
        const Pose& t = seqs[i].pose;
        const Pose& r = nav[i].reported;
        EXPECT_EQ(nav[i].truth.position, t.position);
        const Eigen::Vector3d d = r.position - t.position;
        const double h = wrap(r.yaw - t.yaw);
        sx += d.x();
        sxx += d.x() * d.x();
        syy += d.y() * d.y();
        szz += d.z() * d.z();
        sh += h;
        shh += (h - 0.5 * kDegToRad) * (h - 0.5 * kDegToRad);
        srr += (r.roll - t.roll) * (r.roll - t.roll);
        spp += (r.pitch - t.pitch) * (r.pitch - t.pitch);
    }
    const double n = static_cast<double>(seqs.size());
    EXPECT_NEAR(sx / n, 0.0, 0.002);
    EXPECT_NEAR(std::sqrt(sxx / n), 0.02, 0.001);
    EXPECT_NEAR(std::sqrt(syy / n), 0.02, 0.001);
    EXPECT_NEAR(std::sqrt(szz / n), 0.01, 0.0005);
    EXPECT_NEAR(sh / n / kDegToRad, 0.5, 0.02);
    EXPECT_NEAR(std::sqrt(shh / n) / kDegToRad, 0.2, 0.01);
    EXPECT_NEAR(std::sqrt(srr / n) / kDegToRad, 0.1, 0.005);
    EXPECT_NEAR(std::sqrt(spp / n) / kDegToRad, 0.1, 0.005);
}

TEST_F(NavigationTest, DriftRmsIsTheFractionOfTheMissionDistanceAtItsEnd) {
    // 201 sequences of 0.05 m: a 10 m mission. Over 400 seeds the horizontal
    // rms of the drift at the end is drift_fraction x 10 m, and at distance d
    // drift_fraction x sqrt(10 m x d); the drift has no vertical part.
    const double f = 0.01;
    double end_sq = 0, quarter_sq = 0;
    const int seeds = 400;
    for (int seed = 1; seed <= seeds; ++seed) {
        const Scenario s = load(yaml("navigation: {drift_fraction: 0.01}\n", 201, 0.05, seed));
        const auto seqs = buildSequences(s);
        ASSERT_NEAR(plannedPathLength(seqs), 10.0, 1e-9);
        const auto nav = reportNavigation(s, seqs);
        EXPECT_EQ(nav.front().drift, Eigen::Vector2d::Zero());
        EXPECT_EQ(nav.back().reported.position.z(), seqs.back().pose.position.z());
        end_sq += nav.back().drift.squaredNorm();
        quarter_sq += nav[50].drift.squaredNorm();  // after 2.5 m
    }
    // Relative standard error of an rms of 2 x 400 Gaussians: about 2.5 %.
    EXPECT_NEAR(std::sqrt(end_sq / seeds), f * 10.0, 0.1 * f * 10.0);
    EXPECT_NEAR(std::sqrt(quarter_sq / seeds), f * std::sqrt(10.0 * 2.5), 0.1 * f * 5.0);
}

TEST_F(NavigationTest, SeedDrawsTheErrorsAndOtherStreamsStayPut) {
    const std::string blocks = "navigation: {position_noise: 0.02, drift_fraction: 0.005}\n";
    const Scenario a = load(yaml(blocks, 50, 0.01, 7)), b = load(yaml(blocks, 50, 0.01, 7)),
                   c = load(yaml(blocks, 50, 0.01, 8));
    const auto na = reportNavigation(a, buildSequences(a)), nb = reportNavigation(b, buildSequences(b)),
               nc = reportNavigation(c, buildSequences(c));
    for (std::size_t i = 0; i < na.size(); ++i) {
        EXPECT_EQ(na[i].reported.position, nb[i].reported.position);
        EXPECT_NE(na[i].reported.position, nc[i].reported.position);
    }
}

TEST_F(NavigationTest, LatencyReportsTheTruthOfEarlier) {
    // 0.1 m/s north (0.005 m per 50 ms), latency 0.12 s: NAV is 12 mm behind,
    // interpolated between sequences, continued back before the pass starts.
    const Scenario s = load(yaml("navigation: {latency: 0.12}\n", 40, 0.005));
    const auto seqs = buildSequences(s);
    const auto nav = reportNavigation(s, seqs);
    for (std::size_t i = 0; i < seqs.size(); ++i) {
        EXPECT_NEAR(nav[i].reported.position.x(), seqs[i].pose.position.x() - 0.012, 1e-12) << i;
        EXPECT_EQ(nav[i].reported.position.y(), seqs[i].pose.position.y());
        EXPECT_NEAR(nav[i].reported.yaw, seqs[i].pose.yaw, 1e-15);
    }
    EXPECT_NEAR(nav[0].reported.position.x(), -0.012, 1e-12);  // before the first sequence
    // With motion, the lagged truth carries the motion of the earlier time too.
    const Scenario m = load(yaml("navigation: {latency: 0.5}\nmotion: {roll_amplitude_deg: 3, period: 2}\n", 40));
    const auto mseq = buildSequences(m);
    const auto mnav = reportNavigation(m, mseq);
    const MotionModel motion(m.motion, m.seed);
    for (std::size_t i = 0; i < mseq.size(); ++i) {
        const double t = static_cast<double>(mseq[i].utime - m.trajectory.start_utime) * 1e-6 - 0.5;
        EXPECT_NEAR(mnav[i].reported.roll, motion.at(t).roll, 1e-12) << i;
    }
}

TEST_F(NavigationTest, MotionOscillatesAboutThePlannedPath) {
    const Scenario s = load(yaml("motion: {roll_amplitude_deg: 3, pitch_amplitude_deg: 2, yaw_amplitude_deg: 1,"
                                 " heave_amplitude: 0.05, period: 6}\n",
                                 240));  // 12 s: two periods
    const auto seqs = buildSequences(s);
    const MotionModel motion(s.motion, s.seed);
    const auto& ph = motion.phases();
    EXPECT_NE(ph[0], ph[1]);
    EXPECT_NE(ph[1], ph[2]);
    double max_roll = 0, max_pitch = 0, max_yaw = 0, max_heave = 0;
    for (const SequenceState& q : seqs) {
        EXPECT_EQ(q.planned.roll, 0.0);
        EXPECT_EQ(q.planned.pitch, 0.0);
        EXPECT_EQ(q.pose.position.head<2>(), q.planned.position.head<2>());  // horizontal path unchanged
        max_roll = std::max(max_roll, std::fabs(q.pose.roll));
        max_pitch = std::max(max_pitch, std::fabs(q.pose.pitch));
        max_yaw = std::max(max_yaw, std::fabs(wrap(q.pose.yaw - q.planned.yaw)));
        max_heave = std::max(max_heave, std::fabs(q.pose.position.z() - q.planned.position.z()));
    }
    // Sampled at 50 ms: the peaks are within 0.3 % of the amplitudes.
    EXPECT_NEAR(max_roll / kDegToRad, 3.0, 0.01);
    EXPECT_NEAR(max_pitch / kDegToRad, 2.0, 0.01);
    EXPECT_NEAR(max_yaw / kDegToRad, 1.0, 0.01);
    EXPECT_NEAR(max_heave, 0.05, 0.0002);
    // Periodic: sequence k and k + 120 (6 s later) have the same attitude and heave.
    for (std::size_t k = 0; k + 120 < seqs.size(); ++k) {
        EXPECT_NEAR(seqs[k].pose.roll, seqs[k + 120].pose.roll, 1e-12);
        EXPECT_NEAR(seqs[k].pose.position.z(), seqs[k + 120].pose.position.z(), 1e-12);
    }
    // The true vertical velocity is the heave rate.
    for (std::size_t k = 1; k + 1 < seqs.size(); ++k) {
        const double dz = (seqs[k + 1].pose.position.z() - seqs[k - 1].pose.position.z()) / 0.1;
        EXPECT_NEAR(seqs[k].velocity.z(), dz, 0.05 * 2 * M_PI / 6 * 0.01);
    }
    // Another seed, other phases.
    const MotionModel other(s.motion, s.seed + 1);
    EXPECT_NE(other.phases()[0], ph[0]);
}

TEST_F(NavigationTest, SonarsAreTracedFromTheTruePose) {
    // Motion only: NAV is the truth (NAV and NAV_TRUTH identical), and the sonars
    // see the rolled, pitched, heaving vehicle, not the level one.
    const Scenario s = load(yaml("motion: {roll_amplitude_deg: 3, pitch_amplitude_deg: 2, heave_amplitude: 0.05,"
                                 " period: 6}\n"));
    const Scenario level = load(yaml(""));
    const Simulator sim(s), flat(level);
    int ps_differs = 0;
    for (std::size_t i = 0; i < sim.sequences().size(); ++i) {
        const SequenceOutput o = sim.simulate(sim.sequences()[i]);
        const SequenceOutput l = flat.simulate(flat.sequences()[i]);
        ASSERT_TRUE(o.has_truth);
        EXPECT_FALSE(l.has_truth);
        EXPECT_EQ(encodeMessage(o.nav), encodeMessage(o.truth));
        EXPECT_EQ(o.truth.rpy[0], sim.sequences()[i].pose.roll);
        EXPECT_EQ(o.truth.position_ned[2], sim.sequences()[i].pose.position.z());
        ps_differs += o.ps.intensity != l.ps.intensity;
    }
    EXPECT_EQ(ps_differs, static_cast<int>(sim.sequences().size()));
}

TEST_F(NavigationTest, TruthChannelIsConfigurableAndPublishedLive) {
    const Scenario s = load(yaml(std::string(kIssueBlocks) + "channels: {nav_truth: GROUND_TRUTH}\n"));
    const Simulator sim(s);
    lcm::LCM lcm("memq://");
    ASSERT_TRUE(lcm.good());
    std::vector<std::string> received;
    struct Recorder {
        std::vector<std::string>* out;
        void handle(const lcm::ReceiveBuffer*, const std::string& channel) { out->push_back(channel); }
    } recorder{&received};
    lcm.subscribe(".*", &Recorder::handle, &recorder);
    LivePublisher live(lcm, 0.0);
    sim.run(1, -1, [&](const SequenceOutput& out) {
        writeSequence(live, s.channels, out);
        while (lcm.handleTimeout(0) > 0) {
        }
    });
    const auto n = sim.sequences().size();
    EXPECT_EQ(std::count(received.begin(), received.end(), "GROUND_TRUTH"), static_cast<long>(n));
    EXPECT_EQ(std::count(received.begin(), received.end(), "NAV"), static_cast<long>(n));
    EXPECT_EQ(std::count(received.begin(), received.end(), "NAV_TRUTH"), 0);
}

}  // namespace
}  // namespace sonarfusion::sim
