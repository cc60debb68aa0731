#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "sonarfusion/object_detector.hpp"

using namespace sonarfusion;

namespace {
// The detector as a checkpoint restores it (resume is byte-exact), into one made with `cfg`.
ObjectDetector restoredFromCheckpoint(const ObjectDetector& det, const DetectorConfig& cfg = DetectorConfig{}) {
    std::vector<uint8_t> buf(1 << 20);
    StateWriter w(buf.data(), buf.size());
    det.saveState(w);
    ObjectDetector restored{cfg};
    StateReader r(buf.data(), w.size());
    EXPECT_TRUE(restored.loadState(r));
    return restored;
}
}  // namespace

TEST(ObjectDetector, FiresOnARisingProfileAndCentresOnIt) {
    ObjectDetector det{DetectorConfig{}};
    std::mt19937 rng(1);
    std::normal_distribution<double> noise(0.0, 0.02);
    int fired_at = -1;
    for (int i = 0; i < 400 && fired_at < 0; ++i) {
        const double x = i * 0.01;
        // Seabed at 20 m; from x = 2.0 m an object 1 m tall.
        const double z = (x >= 2.0 ? 19.0 : 20.0) + noise(rng);
        if (det.addEchoPoint(Eigen::Vector3d(x, 0.0, z))) fired_at = i;
    }
    ASSERT_GE(fired_at, 0);
    EXPECT_EQ(fired_at, 204);  // the fifth risen ping (min_consecutive = 5)
    ASSERT_TRUE(det.detection().has_value());
    EXPECT_NEAR(det.detection()->x(), 2.02, 1e-9);
    EXPECT_NEAR(det.detection()->z(), 19.0, 0.05);
    EXPECT_NEAR(*det.baseline(), 20.0, 0.02);
}

TEST(ObjectDetector, StaysQuietOnFlatNoisySeabedWithSpikes) {
    ObjectDetector det{DetectorConfig{}};
    std::mt19937 rng(2);
    std::normal_distribution<double> noise(0.0, 0.05);
    for (int i = 0; i < 20000; ++i) {
        double z = 20.0 + 0.03 * std::sin(i * 0.01) + noise(rng);
        if (i % 97 == 0) z -= 2.0;  // isolated water-column spikes (fish, speckle)
        ASSERT_FALSE(det.addEchoPoint(Eigen::Vector3d(i * 0.005, 0.0, z))) << "false detection at ping " << i;
    }
    EXPECT_FALSE(det.detected());
}

TEST(ObjectDetector, NeedsABaselineFirstAndIgnoresNonFinite) {
    ObjectDetector det{DetectorConfig{}};
    // An object right at the start: no baseline yet, so no detection.
    for (int i = 0; i < 10; ++i) EXPECT_FALSE(det.addEchoPoint(Eigen::Vector3d(0, 0, 19.0)));
    EXPECT_FALSE(det.addEchoPoint(Eigen::Vector3d(std::nan(""), 0, 19.0)));
    EXPECT_FALSE(det.baseline().has_value());
    det.reset();
    EXPECT_FALSE(det.detected());
}

// A seabed sloping 5 deg along the track: the old level baseline called the
// upslope a rise; the fitted plane does not.
TEST(ObjectDetector, ASlopingSeabedIsNotARise) {
    ObjectDetector det{DetectorConfig{}};
    std::mt19937 rng(3);
    std::normal_distribution<double> noise(0.0, 0.03);
    const double slope = std::tan(5.0 * M_PI / 180.0);
    for (int i = 0; i < 20000; ++i) {
        const double x = i * 0.005 - 20.0, y = 0.6 * std::sin(i * 0.3);  // a sweeping PS footprint
        ASSERT_FALSE(det.addEchoPoint(Eigen::Vector3d(x, y, 20.0 - slope * x + noise(rng))))
            << "false detection at ping " << i;
    }
}

// A low object (0.25 m) seen in short bursts of a sector scan, off the centre
// line: risen echoes gather at the object even though no five come in a row.
TEST(ObjectDetector, FiresOnALowObjectSeenInBurstsAndCentresOnIt) {
    ObjectDetector det{DetectorConfig{}};
    std::mt19937 rng(4);
    std::normal_distribution<double> noise(0.0, 0.03);
    bool fired = false;
    for (int i = 0; i < 4000 && !fired; ++i) {
        const bool on_object = i > 400 && i % 44 < 3;  // 3 pings of every 44-ping sweep
        const double x = on_object ? 1.0 + 0.05 * (i % 3) : (i % 44) * 0.2 - 4.0;
        const double z = (on_object ? 19.75 : 20.0) + noise(rng);
        fired = det.addEchoPoint(Eigen::Vector3d(x, 0.7, z));
    }
    ASSERT_TRUE(fired);
    EXPECT_NEAR(det.detection()->x(), 1.05, 0.1);
    EXPECT_NEAR(det.detection()->z(), 19.75, 0.05);
}

// A rough seabed (±10 cm relief, 1-3 m wavelengths) seen as a PS sees it: the
// crests facing the sonar return the strongest echoes, so echoes come mostly
// from the upper part of the relief. Its scatter must be measured on both
// sides of the plane (a version that measured it below the plane alone fired
// on the suite's rough seabed; that case is end to end in the suite, whose
// object-free scenarios check the detector never fires).
TEST(ObjectDetector, ARoughSeabedSeenMostlyOnItsCrestsIsNotARise) {
    ObjectDetector det{DetectorConfig{}};
    std::mt19937 rng(5);
    std::normal_distribution<double> noise(0.0, 0.02);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    int fed = 0;
    for (int i = 0; fed < 30000; ++i) {
        const double x = i * 0.005 - 20.0, y = -1.0 + 0.6 * std::sin(i * 0.3);
        const double relief = 0.07 * std::sin(2 * M_PI * x / 2.3) + 0.03 * std::sin(2 * M_PI * (x + y) / 1.1);
        if (relief < 0.02 && u(rng) < 0.8) continue;  // troughs and flanks mostly in shadow
        ++fed;
        ASSERT_FALSE(det.addEchoPoint(Eigen::Vector3d(x, y, 20.0 - relief + noise(rng))))
            << "false detection at x " << x;
    }
}

// The FLS judges its returns against the seabed plane around the newest echo
// (seabedAtNewestEcho, docs/algorithm.md "Off-swath parts"). It is cached
// between echoes, so it must follow every new echo, match a fresh fit there,
// and come out the same from a restored checkpoint (resume is byte-exact).
TEST(ObjectDetector, TheSeabedAtTheNewestEchoFollowsEveryEchoAndSurvivesACheckpoint) {
    ObjectDetector det{DetectorConfig{}};
    EXPECT_FALSE(det.seabedAtNewestEcho().has_value());
    const double slope = std::tan(3.0 * M_PI / 180.0);
    auto depth = [&](double x) { return 20.0 - slope * x; };
    std::optional<SeabedFit> before;
    for (int i = 0; i < 600; ++i) {
        const double x = i * 0.01, y = 0.5 * std::sin(i * 0.3);
        (void)det.addEchoPoint(Eigen::Vector3d(x, y, depth(x)));
        const std::optional<SeabedFit>& f = det.seabedAtNewestEcho();
        const std::optional<SeabedFit> fresh = det.seabedAt(Eigen::Vector2d(x, y));
        ASSERT_EQ(f.has_value(), fresh.has_value()) << "echo " << i;
        if (!f) continue;
        EXPECT_EQ(f->depth, fresh->depth);
        EXPECT_EQ(f->gradient, fresh->gradient);
        EXPECT_NEAR(f->depthAt(Eigen::Vector2d(x + 4.0, y)), depth(x + 4.0), 0.02) << "echo " << i;
        before = f;
    }
    ASSERT_TRUE(before.has_value());
    const ObjectDetector restored = restoredFromCheckpoint(det);
    ASSERT_TRUE(restored.seabedAtNewestEcho().has_value());
    EXPECT_EQ(restored.seabedAtNewestEcho()->depth, before->depth);
    EXPECT_EQ(restored.seabedAtNewestEcho()->gradient, before->gradient);
    det.reset();
    EXPECT_FALSE(det.seabedAtNewestEcho().has_value());
}

// UpdateConfig::fls_seabed_at_footprint (docs/algorithm.md, "The seabed the FLS
// judges against"). A box face and top the PS saw before any seabed went into
// the seabed ring (no plane yet to call them risen); the seabed echoes after
// them cannot outvote a trim that starts from all echoes, so the plane judged
// for rises stood lifted (DetectorConfig::rise_from_lower_envelope off), with a
// scatter that hides any rise. Fitted from the lower envelope, the same echoes
// give the seabed.
static void feedABoxSeenBeforeTheSeabed(ObjectDetector& det) {
    std::mt19937 rng(3);
    std::normal_distribution<double> noise(0.0, 0.03);
    for (int i = 0; i < 14; ++i)  // the front face at x = -1, 1 m tall, top to foot
        (void)det.addEchoPoint(Eigen::Vector3d(-1.0, 0.0, 19.0 + i / 13.0));
    for (int i = 0; i < 40; ++i)  // the top, 1 m up
        (void)det.addEchoPoint(Eigen::Vector3d(-1.0 + i * 0.05, 0.0, 19.0 + noise(rng)));
    for (int i = 0; i < 80; ++i)  // the seabed before the box, swept back and forth
        (void)det.addEchoPoint(Eigen::Vector3d(-1.1 - 2.0 * std::fabs(std::sin(i * 0.1)), 0.0, 20.0 + noise(rng)));
}

TEST(ObjectDetector, ObjectEchoesTakenBeforeAnyPlaneDoNotLiftTheFootprintSeabed) {
    DetectorConfig trim_from_all;
    trim_from_all.rise_from_lower_envelope = false;
    ObjectDetector det{trim_from_all};
    feedABoxSeenBeforeTheSeabed(det);
    const Eigen::Vector2d box_middle(0.0, 0.0);
    const std::optional<SeabedFit> rise = det.seabedAt(box_middle);
    ASSERT_TRUE(rise.has_value());
    // What the FLS judged against before: lifted, or scattered past any rise.
    EXPECT_TRUE(rise->depthAt(box_middle) < 19.8 || rise->rms > 0.1)
        << "depth " << rise->depthAt(box_middle) << " rms " << rise->rms;
    // The FLS at 3.12 m altitude, 3.7 m before the box's middle, looking down 40 deg at it.
    const Eigen::Vector3d fls(-3.7, 0.0, 16.88);
    const Eigen::Vector3d boresight(std::cos(40.0 * M_PI / 180.0), 0.0, std::sin(40.0 * M_PI / 180.0));
    const std::optional<SeabedFit> footprint = det.seabedAlongRay(fls, boresight);
    ASSERT_TRUE(footprint.has_value());
    EXPECT_NEAR(footprint->depthAt(box_middle), 20.0, 0.05);
    EXPECT_LT(footprint->rms, 0.06);
}

// DetectorConfig::rise_from_lower_envelope (docs/algorithm.md, "A mission that
// starts close to an object"). The same early box echoes lifted the plane rises
// are judged against too, so the box never rose above it and was never
// detected. Started from the lower envelope, that plane is the seabed, and the
// box's next echoes rise.
TEST(ObjectDetector, ObjectEchoesTakenBeforeAnyPlaneDoNotLiftThePlaneRisesAreJudgedAgainst) {
    for (const bool lower_envelope : {false, true}) {
        DetectorConfig cfg;
        cfg.rise_from_lower_envelope = lower_envelope;
        cfg.judge_early_echoes = false;  // only the new echoes below
        ObjectDetector det{cfg};
        feedABoxSeenBeforeTheSeabed(det);
        const Eigen::Vector2d box_middle(0.0, 0.0);
        const std::optional<SeabedFit> rise = det.seabedAt(box_middle);
        ASSERT_TRUE(rise.has_value());
        bool fired = false;
        for (int i = 0; i < 10 && !fired; ++i)  // the PS sweeps back onto the top
            fired = det.addEchoPoint(Eigen::Vector3d(-0.5 + 0.1 * i, 0.0, 19.0));
        if (lower_envelope) {
            EXPECT_NEAR(rise->depthAt(box_middle), 20.0, 0.05);
            EXPECT_LT(rise->rms, 0.06);
            EXPECT_TRUE(fired);
            ASSERT_TRUE(det.detection().has_value());
            EXPECT_NEAR(det.detection()->z(), 19.0, 0.05);
        } else {
            EXPECT_TRUE(rise->depthAt(box_middle) < 19.8 || rise->rms > 0.1);
            EXPECT_FALSE(fired);
        }
    }
}

// DetectorConfig::judge_early_echoes_by_tighter_plane. A low object (0.3 m) in the
// PS's first sweeps, before any plane exists, at one end of what becomes the
// first plane's disc: that plane, fitted around the newest echo 1.4 m away,
// leans towards the object's echoes and takes their rise into its scatter, so
// judged by it they often do not rise. The plane fitted where they lie, with
// them at its centre, is the tighter one here, and judged by it they do.
TEST(ObjectDetector, EarlyEchoesAreJudgedByTheTighterPlane) {
    for (const bool tighter : {false, true}) {
        int found = 0;
        for (int seed = 1; seed <= 20; ++seed) {
            DetectorConfig cfg;
            cfg.judge_early_echoes_by_tighter_plane = tighter;
            ObjectDetector det{cfg};
            std::mt19937 rng(seed);
            std::normal_distribution<double> noise(0.0, 0.03);
            std::uniform_real_distribution<double> behind(-3.0, -0.3), unit(0.0, 1.0);
            bool fired = false;
            // Echoes on the track line (the PS places them there): the seabed
            // behind the object, the object's 8 (0.3 m up, x -0.25..0.25), then
            // the seabed ahead in the order the vehicle reaches it. No plane
            // exists until some 1.4 m ahead of the object.
            for (int i = 0; i < 40; ++i) fired |= det.addEchoPoint(Eigen::Vector3d(behind(rng), 0.0, 20.0 + noise(rng)));
            for (int i = 0; i < 8; ++i)
                fired |= det.addEchoPoint(Eigen::Vector3d(-0.25 + 0.07 * i, 0.0, 19.7 + 0.5 * noise(rng)));
            for (int i = 0; i < 80 && !fired; ++i)
                fired |= det.addEchoPoint(Eigen::Vector3d(0.3 + 0.0325 * (i + unit(rng)), 0.0, 20.0 + noise(rng)));
            found += fired;
            if (fired) {
                ASSERT_TRUE(det.detection().has_value());
                EXPECT_NEAR(det.detection()->x(), 0.0, 0.2);
                EXPECT_NEAR(det.detection()->z(), 19.7, 0.05);
            }
        }
        if (tighter)
            EXPECT_EQ(found, 20);
        else
            EXPECT_LT(found, 15);  // 9 of 20
    }
}

// DetectorConfig::judge_early_echoes. The PS's first sweeps cross a boulder
// (0.5 m tall) before any plane exists, then sweep on over bare seabed: the
// boulder's echoes went in as seabed and no later echo falls on it. Judged when
// the first plane exists, they are risen and declare it; left unjudged, the
// boulder is never found on this pass.
TEST(ObjectDetector, EchoesTakenBeforeAnyPlaneAreJudgedWhenOneExists) {
    for (const bool judge : {false, true}) {
        DetectorConfig cfg;
        cfg.judge_early_echoes = judge;
        ObjectDetector det{cfg};
        std::mt19937 rng(6);
        std::normal_distribution<double> noise(0.0, 0.02);
        std::uniform_real_distribution<double> across(-3.0, 3.0);
        int fired = 0;
        for (int i = 0; i < 50; ++i) {  // 3 of every 5 echoes on the boulder, the rest on the seabed around
            const bool boulder = i % 5 < 3;
            const Eigen::Vector3d p = boulder ? Eigen::Vector3d(0.3 + 0.01 * i, 0.5, 19.5 + noise(rng))
                                              : Eigen::Vector3d(-2.5 + 0.1 * i, across(rng), 20.0 + noise(rng));
            fired += det.addEchoPoint(p);
        }
        EXPECT_EQ(fired, 0);  // no plane yet: nothing judged
        for (int i = 0; i < 300; ++i) {  // bare seabed, never within 0.6 m of the boulder
            Eigen::Vector3d p(across(rng), across(rng), 20.0 + noise(rng));
            if ((p.head<2>() - Eigen::Vector2d(0.55, 0.5)).norm() < 0.6) continue;
            fired += det.addEchoPoint(p);
        }
        if (judge) {
            EXPECT_EQ(fired, 1);
            ASSERT_TRUE(det.detection().has_value());
            EXPECT_NEAR(det.detection()->x(), 0.55, 0.2);
            EXPECT_NEAR(det.detection()->z(), 19.5, 0.05);
            // The boulder's echoes left the seabed's fits: the plane over it is the seabed.
            const std::optional<SeabedFit> f = det.seabedAt(Eigen::Vector2d(0.55, 0.5));
            ASSERT_TRUE(f.has_value());
            EXPECT_NEAR(f->depthAt(Eigen::Vector2d(0.55, 0.5)), 20.0, 0.03);
            // And a checkpoint keeps which echoes those were.
            const ObjectDetector restored = restoredFromCheckpoint(det);
            const std::optional<SeabedFit> g = restored.seabedAt(Eigen::Vector2d(0.55, 0.5));
            ASSERT_TRUE(g.has_value());
            EXPECT_EQ(g->depth, f->depth);
            EXPECT_EQ(g->echoes, f->echoes);
        } else {
            EXPECT_EQ(fired, 0);
        }
    }
}

// The PS head sweeps its look 3-9 m ahead: its newest echo often lies where no
// seabed echo was gathered yet, and the plane there does not exist. The FLS
// footprint, nearer, lies over echoes gathered on the way.
TEST(ObjectDetector, TheFootprintSeabedStandsWhereTheNewestEchoHasNone) {
    ObjectDetector det{DetectorConfig{}};
    for (int i = 0; i < 300; ++i)
        (void)det.addEchoPoint(Eigen::Vector3d(i * 0.02, 0.3 * std::sin(i * 0.7), 20.0 + 0.01 * std::sin(i * 1.3)));
    (void)det.addEchoPoint(Eigen::Vector3d(12.0, 0.0, 20.0));  // the far end of a sweep
    EXPECT_FALSE(det.seabedAtNewestEcho().has_value());
    const Eigen::Vector3d fls(4.0, 0.0, 16.88);
    const Eigen::Vector3d boresight(std::cos(40.0 * M_PI / 180.0), 0.0, std::sin(40.0 * M_PI / 180.0));
    const std::optional<SeabedFit> footprint = det.seabedAlongRay(fls, boresight);
    ASSERT_TRUE(footprint.has_value());
    EXPECT_NEAR(footprint->depthAt(Eigen::Vector2d(7.7, 0.0)), 20.0, 0.02);
    // Nothing at all before any echo; a restored checkpoint gives the same plane.
    EXPECT_FALSE(ObjectDetector{DetectorConfig{}}.seabedAlongRay(fls, boresight).has_value());
    const std::optional<SeabedFit> again = restoredFromCheckpoint(det).seabedAlongRay(fls, boresight);
    ASSERT_TRUE(again.has_value());
    EXPECT_EQ(again->depth, footprint->depth);
    EXPECT_EQ(again->gradient, footprint->gradient);
}

// The lower-envelope trim's first cut is level (the median depth): on a sloping
// seabed it keeps the downhill half, a part of the same plane, and the passes
// after it take the whole slope back, so the slope is neither flattened nor
// shifted (a 5 deg slope across the fit radius spans 0.5 m of depth).
TEST(ObjectDetector, TheFootprintSeabedFollowsASlope) {
    ObjectDetector det{DetectorConfig{}};
    std::mt19937 rng(5);
    std::normal_distribution<double> noise(0.0, 0.03);
    const double slope = std::tan(5.0 * M_PI / 180.0);
    auto depth = [&](double x, double y) { return 20.0 - slope * x + 0.5 * slope * y; };
    for (int i = 0; i < 500; ++i) {
        const double x = i * 0.02, y = 0.6 * std::sin(i * 0.37);
        (void)det.addEchoPoint(Eigen::Vector3d(x, y, depth(x, y) + noise(rng)));
    }
    const Eigen::Vector3d fls(6.0, 0.0, depth(6.0, 0.0) - 3.0);
    const Eigen::Vector3d boresight(std::cos(40.0 * M_PI / 180.0), 0.0, std::sin(40.0 * M_PI / 180.0));
    const std::optional<SeabedFit> f = det.seabedAlongRay(fls, boresight);
    ASSERT_TRUE(f.has_value());
    for (double x : {7.0, 8.0, 9.0}) EXPECT_NEAR(f->depthAt(Eigen::Vector2d(x, 0.0)), depth(x, 0.0), 0.02) << x;
    EXPECT_NEAR(f->gradient.x(), -slope, 0.01);
    EXPECT_LT(f->rms, 0.05);
    EXPECT_GT(f->rms, 0.015);  // the seabed's own scatter, both sides, not the lower half's
}

// DetectorConfig::seabed_across_lines (docs/algorithm.md, "Two lines on a
// slope across them"): the PS places its echoes on the track line, so two
// passes 2 m apart over a 5 deg slope across them leave two lines of echoes
// 0.17 m apart in depth. The second line's seabed is not a rise, and an object
// on it still is.
TEST(ObjectDetector, ALineBesideAnEarlierOneOnASlopeAcrossThemIsNotARise) {
    const double slope = std::tan(5.0 * M_PI / 180.0);
    auto depth = [&](double y) { return 20.0 - slope * y; };  // rising towards +y
    for (const bool across : {false, true}) {
        DetectorConfig cfg;
        cfg.seabed_across_lines = across;
        ObjectDetector det{cfg};
        std::mt19937 rng(9);
        std::normal_distribution<double> noise(0.0, 0.02);
        int fired = 0;
        for (int i = 0; i < 400; ++i)  // pass 1, north along y = -1
            fired += det.addEchoPoint(Eigen::Vector3d(i * 0.02, -1.0, depth(-1.0) + noise(rng)));
        EXPECT_EQ(fired, 0);
        int fired_bare = 0, fired_post = 0;
        for (int i = 0; i < 400; ++i) {  // pass 2, south along y = +1 (uphill), a 0.3 m post at x 2
            const double x = 8.0 - i * 0.02;
            const bool post = std::fabs(x - 2.0) < 0.2;
            const bool risen = det.addEchoPoint(Eigen::Vector3d(x, 1.0, depth(1.0) - (post ? 0.3 : 0.0) + noise(rng)));
            (x > 2.6 ? fired_bare : fired_post) += risen;
            if (risen && across) {
                EXPECT_NEAR(det.detection()->x(), 2.0, 0.3) << "declared on bare seabed at echo " << i;
            }
        }
        if (!across) {
            EXPECT_GT(fired_bare, 0);  // the uphill line's bare seabed declared objects
            continue;
        }
        EXPECT_EQ(fired_bare, 0);
        EXPECT_GE(fired_post, 1);  // the detector stays armed: fresh echoes of the post declare again
        const std::optional<SeabedFit> f = det.seabedAt(Eigen::Vector2d(4.0, 1.0));
        ASSERT_TRUE(f.has_value());
        EXPECT_NEAR(f->depthAt(Eigen::Vector2d(4.0, 1.0)), depth(1.0), 0.03);
        EXPECT_NEAR(f->gradient.y(), -slope, 0.02);
    }
}

// DetectorConfig::envelope_per_line (docs/algorithm.md, "A new line beside a
// dense old one"): a line just begun 2 m uphill of a dense old one on a 5 deg
// slope across them. The lower envelope's second halving, one cut over the
// disc, is decided by the old line's hundreds of echoes; when it keeps one or
// two of the new line's handful, the plane's tilt across sags, the 3-scatter
// window (narrowed by the halvings) drops the new line, the tilt goes level
// and the new line's seabed stands 0.17 m above it. Halved per line, each line
// keeps its quarter and the tilt holds. Over these 40 noise draws the old cut
// lost the tilt in one, the per-line cut in none.
TEST(ObjectDetector, ANewLineBesideADenseOldOneKeepsTheTiltAcross) {
    const double slope = std::tan(5.0 * M_PI / 180.0);
    auto depth = [&](double y) { return 20.0 - slope * y; };  // rising towards +y
    for (const bool per_line : {false, true}) {
        int tilt_lost = 0, fired = 0;
        for (int seed = 1; seed <= 40; ++seed) {
            DetectorConfig cfg;
            cfg.envelope_per_line = per_line;
            ObjectDetector det{cfg};
            std::mt19937 rng(seed);
            std::normal_distribution<double> noise(0.0, 0.02);
            for (double x = 18.0; x < 26.1; x += 0.0075)  // the old line, 7.5 mm per echo (the ring holds 7.7 m)
                fired += det.addEchoPoint(Eigen::Vector3d(x, -1.0, depth(-1.0) + noise(rng)));
            bool lost = false;
            for (double x = 21.25; x < 24.0; x += 0.125) {  // the new line, beside the old one's last 5 m
                fired += det.addEchoPoint(Eigen::Vector3d(x, 1.0, depth(1.0) + noise(rng)));
                if (const std::optional<SeabedFit> f = det.seabedAt(Eigen::Vector2d(x, 1.0)))
                    lost = lost || std::fabs(f->gradient.y() + slope) > 0.02;
            }
            tilt_lost += lost;
        }
        if (per_line) {
            EXPECT_EQ(tilt_lost, 0);
            EXPECT_EQ(fired, 0);
        } else {
            EXPECT_GE(tilt_lost, 1);
        }
    }
}

// DetectorConfig::nearest_echo_sigmas, the detector's side: a ping's nearer
// echo is judged against the plane its strongest (seabed) echo was, counts as
// its one risen echo, and never joins the seabed's fits.
TEST(ObjectDetector, ANearerEchoRisesWhereTheStrongestIsTheSeabeds) {
    ObjectDetector with{DetectorConfig{}}, without{DetectorConfig{}};
    int fired = -1;
    for (int i = 0; i < 300; ++i) {
        const Eigen::Vector3d seabed(i * 0.01, 0.0, 20.0 + 0.01 * std::sin(i * 0.7));
        const bool over_post = i >= 200;
        // Over the post: the nearer echo stands 0.5 m up; elsewhere it is the
        // seabed's own leading edge, 2 cm up (under the rise threshold).
        const Eigen::Vector3d nearer(2.0, 0.0, over_post ? 19.5 : seabed.z() - 0.02);
        if (with.addEchoPoint(seabed, nearer) && fired < 0) fired = i;
        EXPECT_FALSE(without.addEchoPoint(seabed));
    }
    EXPECT_EQ(fired, 204);  // the fifth ping over the post
    ASSERT_TRUE(with.detection().has_value());
    EXPECT_NEAR(with.detection()->z(), 19.5, 1e-9);
    // The seabed under the newest echo is the seabed's, not lifted toward the post.
    EXPECT_NEAR(*with.baseline(), 20.0, 0.02);
    // With no strongest echo at all, a nearest echo that rises still counts.
    ObjectDetector weak{DetectorConfig{}};
    for (int i = 0; i < 200; ++i) EXPECT_FALSE(weak.addEchoPoint(Eigen::Vector3d(i * 0.01, 0.0, 20.0)));
    for (int i = 0; i < 4; ++i) EXPECT_FALSE(weak.addNearestEcho(Eigen::Vector3d(2.0, 0.0, 19.5)));
    EXPECT_FALSE(weak.addNearestEcho(Eigen::Vector3d(1.9, 0.0, 19.99)));  // not risen
    EXPECT_TRUE(weak.addNearestEcho(Eigen::Vector3d(2.0, 0.0, 19.5)));
}

// DetectorConfig::fls_shadow_min_frames: FLS shadows gather in a ring of their
// own; one frame's shadow declares nothing, a second within cluster_radius
// declares an object at their mean, and the pair is spent.
TEST(ObjectDetector, ShadowsFromTwoFramesDeclareAnObject) {
    DetectorConfig cfg;
    ObjectDetector det(cfg);
    EXPECT_FALSE(det.addShadow(Eigen::Vector3d(4.0, 1.0, 20.0)));
    EXPECT_FALSE(det.addShadow(Eigen::Vector3d(9.0, 1.0, 20.0)));  // far from the first: its own cluster
    EXPECT_FALSE(det.addShadow(Eigen::Vector3d(NAN, 1.0, 20.0)));
    EXPECT_FALSE(det.detected());
    ASSERT_TRUE(det.addShadow(Eigen::Vector3d(4.2, 1.2, 20.0)));
    ASSERT_TRUE(det.detection().has_value());
    EXPECT_NEAR(det.detection()->x(), 4.1, 1e-9);
    EXPECT_NEAR(det.detection()->y(), 1.1, 1e-9);
    EXPECT_EQ(det.detections(), 1);
    EXPECT_FALSE(det.addShadow(Eigen::Vector3d(4.1, 1.1, 20.0)));  // the pair was spent
    // Shadows are not risen echoes: they never count toward min_risen_echoes.
    for (int i = 0; i < cfg.min_risen_echoes - 1; ++i) EXPECT_FALSE(det.addRisenEcho(Eigen::Vector3d(9.0, 1.0, 19.5)));
}

TEST(ObjectDetector, ShadowMinFramesOneDeclaresOnTheFirst) {
    DetectorConfig cfg;
    cfg.fls_shadow_min_frames = 1;
    ObjectDetector det(cfg);
    EXPECT_TRUE(det.addShadow(Eigen::Vector3d(4.0, 1.0, 20.0)));
}

// DetectorConfig::rise_trim_converges (docs/algorithm.md, "A rough seabed
// sloping along the line"): the rise trim's cuts keep echoes by depth, so on a
// rough seabed (swells of +-10 cm) sloping 5 deg diagonally to the line, one
// 3-sigma window left the plane below the seabed with a flattened slope and a
// narrowed scatter, and the seabed's own swells declared objects. Repeating the
// window until it keeps the same echoes finds the seabed's plane.
TEST(ObjectDetector, ARoughSeabedSlopingAlongTheLineIsNotARise) {
    const double slope = std::tan(5.0 * M_PI / 180.0);
    auto depth = [&](double x, double y) {  // the suite's "rough" relief (tools/gen-scenes)
        const double relief = 0.045 * std::sin(2 * M_PI * x / 5.3 + 0.3) * std::cos(2 * M_PI * y / 4.1 + 0.8) +
                              0.025 * std::sin(2 * M_PI * (x - 0.8 * y) / 2.3 + 1.7) +
                              0.018 * std::cos(2 * M_PI * (0.6 * x + y) / 1.7 + 0.2) +
                              0.012 * std::sin(2 * M_PI * (x + 0.3 * y) / 1.1 + 2.9);
        return 20.0 - slope * (x + y) / std::sqrt(2.0) + relief;
    };
    for (const bool converge : {false, true}) {
        DetectorConfig cfg;
        cfg.rise_trim_converges = converge;
        for (const bool post : {false, true}) {  // with a 0.25 m post, 0.4 m across, at x 10 on the first pass
            ObjectDetector det{cfg};
            std::mt19937 rng(11);
            std::normal_distribution<double> noise(0.0, 0.01);
            int fired_bare = 0, fired_post = 0;
            for (int pass = 0; pass < 2; ++pass)
                for (int i = 0; i < 2000; ++i) {
                    const double x = pass == 0 ? i * 0.01 : 20.0 - i * 0.01;
                    const double y = (pass == 0 ? -0.2 : 0.2) + 0.6 * std::sin(i * 0.3);  // a sweeping PS footprint
                    const bool on_post = post && pass == 0 && std::hypot(x - 10.0, y + 0.2) < 0.2;
                    const bool risen = det.addEchoPoint(Eigen::Vector3d(x, y, depth(x, y) - (on_post ? 0.25 : 0.0) + noise(rng)));
                    if (!risen) continue;
                    const bool at_post = post && std::hypot(det.detection()->x() - 10.0, det.detection()->y() + 0.2) < 0.5;
                    (at_post ? fired_post : fired_bare) += 1;
                }
            if (!converge) {
                if (!post) {
                    EXPECT_GT(fired_bare, 0);  // the swells declared objects on bare seabed
                }
                continue;
            }
            EXPECT_EQ(fired_bare, 0) << (post ? "with" : "without") << " the post";
            if (post) {
                EXPECT_GE(fired_post, 1);
            }
        }
    }
}

// DetectorConfig::rise_from_deepest_in_beam. A 2 deg thick PS fan returns from
// anywhere across its thickness: 8 m out at 33 deg depression the same echo may
// lie 0.12 m deeper than its beam's centre. Seabed echoes 0.15 m above a plane
// fitted with 1 cm scatter that could lie 0.10 m deeper are no rise (found on
// object-free seabed at 4.5-5 m altitude); an object 0.15 m tall seen from
// near, where the fan is 0.02 m thick, still is.
TEST(ObjectDetector, AnEchoThatCouldLieOnTheSeabedWithinTheFansThicknessIsNotARise) {
    struct Case {
        bool rule;
        double deeper_by;
        int fired;
    };
    for (const Case c : {Case{true, 0.10, 0}, Case{false, 0.10, 1}, Case{true, 0.02, 1}}) {
        DetectorConfig cfg;
        cfg.rise_from_deepest_in_beam = c.rule;
        ObjectDetector det{cfg};
        std::mt19937 rng(9);
        std::normal_distribution<double> noise(0.0, 0.01);
        std::uniform_real_distribution<double> across(-2.0, 2.0);
        int fired = 0;
        for (int i = 0; i < 200; ++i)  // a level seabed around the spot
            fired += det.addEchoPoint(Eigen::Vector3d(across(rng), across(rng), 20.0 + noise(rng)), c.deeper_by);
        ASSERT_EQ(fired, 0);
        for (int i = 0; i < 8; ++i)  // eight echoes 0.15 m up, within 0.1 m of each other
            fired += det.addEchoPoint(Eigen::Vector3d(0.01 * i, 0.0, 19.85 + noise(rng)), c.deeper_by);
        EXPECT_EQ(fired, c.fired) << "rule " << c.rule << ", deeper_by " << c.deeper_by;
    }
}

// The same for echoes taken before any plane stood where they lie: each keeps
// its own spread down the fan until judged (judge_early_echoes), across a checkpoint.
TEST(ObjectDetector, AnEarlyEchoKeepsItsSpreadDownTheFanUntilJudged) {
    for (const bool rule : {true, false}) {
        DetectorConfig cfg;
        cfg.rise_from_deepest_in_beam = rule;
        ObjectDetector first{cfg};
        std::mt19937 rng(10);
        std::normal_distribution<double> noise(0.0, 0.01);
        std::uniform_real_distribution<double> across(-2.0, 2.0);
        int fired = 0;
        for (int i = 0; i < 8; ++i)  // no plane yet: held unjudged
            fired += first.addEchoPoint(Eigen::Vector3d(0.01 * i, 0.0, 19.85 + noise(rng)), 0.10);
        ASSERT_EQ(fired, 0);
        // The spread is state: it survives a checkpoint.
        ObjectDetector det = restoredFromCheckpoint(first, cfg);
        for (int i = 0; i < 200; ++i) {  // the seabed around them, then judged
            Eigen::Vector3d p(across(rng), across(rng), 20.0 + noise(rng));
            if (p.head<2>().norm() < 0.6) continue;
            fired += det.addEchoPoint(p, 0.01);
        }
        EXPECT_EQ(fired, rule ? 0 : 1) << "rule " << rule;
    }
}
