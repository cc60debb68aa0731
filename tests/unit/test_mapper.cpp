#include <gtest/gtest.h>

#include <memory>

#include "sonarfusion/mapper.hpp"
#include "sonarfusion/variant.hpp"
#include "test_helpers.hpp"

using namespace sonarfusion;

namespace {
constexpr double kDeg = M_PI / 180.0;

// One straight pass over the box world: NAV + PS every 5 mm step, FLS every 4th.
void runPass(Mapper& mapper, const test::BoxWorld& world, int steps, double start_x) {
    const FlsGeometry& g = mapper.config().fls;
    for (int i = 0; i < steps; ++i) {
        const int64_t t = 1000000 + i * 50000LL;
        const TimedPose nav = test::trackPose(t, start_x + 0.005 * i);
        mapper.addNav(nav);
        const double head = test::sectorScanHead(i);
        auto ping = test::simulatePing(world, mapper.psModel(), nav.pose, t, head);
        mapper.addPs(ping.view);
        if (i % 4 == 0) {
            auto frame = test::simulateFrame(world, g, mapper.flsModel(), nav.pose, t);
            mapper.addFls(frame.view);
        }
    }
}
}  // namespace

TEST(Mapper, DetectsTheBoxAnchorsTheMapAndFindsIt) {
    MapperConfig cfg;
    // This synthetic PS fan sees nothing but the box top over the box (its
    // seabed beside the box never echoes), so the echo height field is lifted
    // over the box's far half (a known limit, docs/algorithm.md): the seabed
    // here comes from the occupied surface.
    cfg.segmentation.seabed_from_ps_echoes = false;
    Mapper mapper(cfg);
    test::BoxWorld world;
    runPass(mapper, world, 1600, -6.0);
    const MapperCounters& c = mapper.counters();
    ASSERT_TRUE(mapper.map().initialised());
    EXPECT_EQ(c.map_initialisations, 1);
    // The map is centred near the first part of the box the PS saw.
    EXPECT_LT((mapper.map().centre() - Eigen::Vector3d(-1.0, 0.0, 19.0)).norm(), 1.0);
    EXPECT_EQ(c.nav_used, 1600);
    EXPECT_EQ(c.ps_in, 1600);
    EXPECT_GT(c.fls_used, 300);
    EXPECT_GT(c.by_outcome[static_cast<int>(Outcome::FlsBeforeMap)], 0);

    const SegmentationStats& st = mapper.segment();
    ASSERT_GE(st.objects, 1);
    // The largest object is the box: it covers the box's centre line, stands
    // about as tall as the box (1 m; FLS votes above the top that no PS ray
    // carved add some), and does not spill far past its footprint.
    const ObjectInfo* box = &mapper.segmenter().objects()[0];
    for (const ObjectInfo& o : mapper.segmenter().objects())
        if (o.voxel_count > box->voxel_count) box = &o;
    EXPECT_LT(box->bbox_min.x(), -0.5);
    EXPECT_GT(box->bbox_max.x(), 0.5);
    EXPECT_LT(box->bbox_min.y(), 0.0);
    EXPECT_GT(box->bbox_max.y(), 0.0);
    EXPECT_GT(box->bbox_min.x(), -4.0);
    EXPECT_LT(box->bbox_max.x(), 2.0);
    EXPECT_GT(box->height_m, 0.8);
    // One voxel more than before the voxel-sized FLS arcs and the PS end-point
    // hits (1.6): this idealised world's echoes above the top edge confirm one
    // more layer of FLS votes (docs/algorithm.md, what is still wrong).
    EXPECT_LT(box->height_m, 1.7);
}

TEST(Mapper, CarvingRemovesWhatTheFlsAloneClaims) {
    test::BoxWorld world;
    auto occupied = [&](Variant v) {
        MapperConfig cfg;
        applyVariant(v, cfg);
        Mapper mapper(cfg);
        runPass(mapper, world, 1600, -6.0);
        int n = 0;
        const float thr = static_cast<float>(logOddsFromProbability(0.7));
        for (std::size_t i = 0; i < mapper.map().size(); ++i) n += mapper.map().logOdds(i) > thr;
        return n;
    };
    const int fls_only = occupied(Variant::FlsOnly);
    const int fused = occupied(Variant::Fused);
    EXPECT_GT(fls_only, 0);
    EXPECT_LT(fused, fls_only);
}

TEST(Variant, NamesRoundTripAndPresetsDiffer) {
    for (Variant v : {Variant::FlsOnly, Variant::CarveOnly, Variant::Paper, Variant::Fused})
        EXPECT_EQ(parseVariant(variantName(v)), v);
    EXPECT_FALSE(parseVariant("octomap").has_value());
    MapperConfig c;
    applyVariant(Variant::Paper, c);
    EXPECT_FALSE(c.update.fls_once_per_frame);
    EXPECT_FALSE(c.update.require_ps_observation);
    applyVariant(Variant::Fused, c);
    EXPECT_TRUE(c.update.fls_once_per_frame);
    EXPECT_TRUE(c.update.require_ps_observation);
    applyVariant(Variant::FlsOnly, c);
    EXPECT_FALSE(c.update.ps_carving_enabled);
    applyVariant(Variant::CarveOnly, c);
    EXPECT_FALSE(c.update.fls_enabled);
}

TEST(Mapper, SegmentsAlongTheTrackAxisOfItsNav) {
    MapperConfig cfg;
    Mapper mapper(cfg);
    EXPECT_TRUE(mapper.trackAxis().axis().isZero());
    // Out and back along east-west (yaw +-90 deg), as the reference survey's passes.
    for (int i = 0; i < 10; ++i) mapper.addNav(test::poseAt(1000 + i, 0.0, 0.01 * i, 17.0, M_PI / 2));
    for (int i = 10; i < 20; ++i) mapper.addNav(test::poseAt(1000 + i, 0.0, 0.1 - 0.01 * i, 17.0, -M_PI / 2));
    mapper.initialiseMapAt(Eigen::Vector3d(0.0, 0.0, 20.0));
    mapper.segment();
    EXPECT_NEAR(std::fabs(mapper.segmenter().alongTrack().y()), 1.0, 1e-9);
    EXPECT_NEAR(mapper.segmenter().alongTrack().x(), 0.0, 1e-9);
}

// DetectorConfig::replay_pings (docs/algorithm.md, "A mission that starts close
// to an object"). The PS's first sweeps fall on the box, before the detector
// has a seabed plane to call anything risen, so the map is anchored late. The
// held pings are carved into it when it is: the map is then the one a map
// anchored there before the first ping would have made (carve_only: the PS
// alone, so nothing else differs). Without them it misses those sweeps.
TEST(Mapper, AMapAnchoredLateHoldsThePingsThatFoundTheObject) {
    test::BoxWorld world;
    auto run = [&](int replay_pings, const Eigen::Vector3d* anchor_first) {
        MapperConfig cfg;
        applyVariant(Variant::CarveOnly, cfg);
        cfg.detector.replay_pings = replay_pings;
        cfg.detector.replay_pings_carve_only = false;  // echoes too: as if the map had existed
        auto mapper = std::make_unique<Mapper>(cfg);
        if (anchor_first) mapper->initialiseMapAt(*anchor_first);
        runPass(*mapper, world, 1000, -4.5);
        return mapper;
    };
    const auto late = run(1024, nullptr);
    ASSERT_TRUE(late->map().initialised());
    EXPECT_EQ(late->counters().map_initialisations, 1);
    EXPECT_GT(late->counters().ps_pings_replayed, 0);
    const Eigen::Vector3d centre = late->map().centre();
    const auto early = run(1024, &centre);
    const auto unheld = run(0, nullptr);
    ASSERT_TRUE(unheld->map().initialised());
    ASSERT_EQ(unheld->map().centre(), centre);
    EXPECT_EQ(unheld->counters().ps_pings_replayed, 0);
    int differ_early = 0, differ_unheld = 0, observed_late = 0, observed_unheld = 0;
    for (std::size_t i = 0; i < late->map().size(); ++i) {
        differ_early += late->map().logOdds(i) != early->map().logOdds(i);
        differ_unheld += late->map().logOdds(i) != unheld->map().logOdds(i);
        observed_late += late->map().psObserved(i);
        observed_unheld += unheld->map().psObserved(i);
    }
    EXPECT_EQ(differ_early, 0);
    EXPECT_GT(differ_unheld, 100);
    EXPECT_GT(observed_late, observed_unheld);
}

// DetectorConfig::replay_pings_carve_only (the default; docs/algorithm.md,
// "The pings before the map carve it"): the held pings add only their water.
// Against a map anchored at the same ping with no pings held, every voxel has
// the same PS echo count (the held pings' echoes, placed across the fan from
// their far looks, are left out) and a log-odds no higher (more carving, and
// the later pings spare less); over a hundred voxels are carved lower. With
// echoes too (the option off), the echo counts differ.
TEST(Mapper, HeldPingsCarveALateMapWithoutAddingTheirEchoes) {
    test::BoxWorld world;
    auto run = [&](int replay_pings, bool carve_only) {
        MapperConfig cfg;
        applyVariant(Variant::CarveOnly, cfg);
        cfg.detector.replay_pings = replay_pings;
        cfg.detector.replay_pings_carve_only = carve_only;
        cfg.detector.replay_risen_pings_whole = false;  // every held ping carves only (next test)
        auto mapper = std::make_unique<Mapper>(cfg);
        runPass(*mapper, world, 1000, -4.5);
        return mapper;
    };
    const auto carved = run(1024, true), full = run(1024, false), unheld = run(0, true);
    for (const auto* m : {carved.get(), full.get(), unheld.get()}) ASSERT_TRUE(m->map().initialised());
    ASSERT_EQ(carved->map().centre(), unheld->map().centre());
    EXPECT_GT(carved->counters().ps_pings_replayed, 0);
    int echoes_differ = 0, higher = 0, lower = 0, full_echoes_differ = 0;
    for (std::size_t i = 0; i < carved->map().size(); ++i) {
        echoes_differ += carved->map().psEchoCount(i) != unheld->map().psEchoCount(i);
        higher += carved->map().logOdds(i) > unheld->map().logOdds(i);
        lower += carved->map().logOdds(i) < unheld->map().logOdds(i);
        full_echoes_differ += full->map().psEchoCount(i) != unheld->map().psEchoCount(i);
    }
    EXPECT_EQ(echoes_differ, 0);
    EXPECT_EQ(higher, 0);
    EXPECT_GT(lower, 100);
    EXPECT_GT(full_echoes_differ, 0);
}

// DetectorConfig::replay_risen_pings_whole (docs/algorithm.md, "The held pings
// that saw the object"). A pass starting over the box's front edge: the PS's first
// echoes fall on the box before any seabed plane, the plane found beyond it
// declares the box from them, and by then the PS sector's near edge has
// reached it. The held pings whose echo rises (the box's) are replayed whole:
// the map gains PS echoes above the seabed, and only there. With the rule off
// no echo count changes. From 4.5 m before the box (previous test) the PS
// still looks at it after the detection, and the rule changes nothing.
TEST(Mapper, HeldPingsThatSawTheObjectAddTheirEchoesToALateMap) {
    test::BoxWorld world;
    auto run = [&](int replay_pings, bool whole, double start_x) {
        MapperConfig cfg;
        applyVariant(Variant::CarveOnly, cfg);
        cfg.detector.replay_pings = replay_pings;
        cfg.detector.replay_pings_carve_only = true;
        cfg.detector.replay_risen_pings_whole = whole;
        auto mapper = std::make_unique<Mapper>(cfg);
        runPass(*mapper, world, 1000, start_x);
        return mapper;
    };
    const auto whole = run(1024, true, -1.0), carved = run(1024, false, -1.0), unheld = run(0, true, -1.0);
    for (const auto* m : {whole.get(), carved.get(), unheld.get()}) ASSERT_TRUE(m->map().initialised());
    ASSERT_EQ(whole->map().centre(), unheld->map().centre());
    const VoxelMap& map = whole->map();
    int more_above = 0, differ_below = 0, carved_differ = 0;
    for (std::size_t i = 0; i < map.size(); ++i) {
        const bool above = map.centreOf(map.fromLinear(i)).z() < world.seabed - map.resolution();
        const int extra = map.psEchoCount(i) - unheld->map().psEchoCount(i);
        more_above += above && extra > 0;
        differ_below += !above && extra != 0;
        carved_differ += carved->map().psEchoCount(i) != unheld->map().psEchoCount(i);
    }
    EXPECT_GT(more_above, 10);
    EXPECT_EQ(differ_below, 0);
    EXPECT_EQ(carved_differ, 0);

    const auto far_whole = run(1024, true, -4.5), far_carved = run(1024, false, -4.5);
    int far_differ = 0;
    for (std::size_t i = 0; i < far_whole->map().size(); ++i)
        far_differ += far_whole->map().psEchoCount(i) != far_carved->map().psEchoCount(i) ||
                      far_whole->map().logOdds(i) != far_carved->map().logOdds(i);
    EXPECT_EQ(far_differ, 0);
}

// DetectorConfig::replay_fls_frames (docs/algorithm.md, "The looks before the
// detection"). The FLS sees the box from 10 m; the PS declares it only when its
// fan reaches it. The held frames are applied to the map when it is anchored,
// each judged against the seabed it was judged against then: the map is the
// one a map anchored there before the first frame would have made (fls_only:
// the FLS alone updates it). Without them it misses those looks.
TEST(Mapper, AMapAnchoredLateHoldsTheFlsFramesThatSawTheObject) {
    test::BoxWorld world;
    auto run = [&](int replay_frames, const Eigen::Vector3d* anchor_first) {
        MapperConfig cfg;
        applyVariant(Variant::FlsOnly, cfg);
        cfg.detector.replay_fls_frames = replay_frames;
        cfg.detector.fls_shadow_false_alarm = 0.0;  // the PS declares
        auto mapper = std::make_unique<Mapper>(cfg);
        if (anchor_first) mapper->initialiseMapAt(*anchor_first);
        runPass(*mapper, world, 1000, -4.5);
        return mapper;
    };
    const auto late = run(256, nullptr);  // holds every frame of the pass
    ASSERT_TRUE(late->map().initialised());
    EXPECT_EQ(late->counters().map_initialisations, 1);
    EXPECT_GT(late->counters().fls_frames_replayed, 10);
    const Eigen::Vector3d centre = late->map().centre();
    const auto early = run(256, &centre);
    const auto unheld = run(0, nullptr);
    ASSERT_TRUE(unheld->map().initialised());
    ASSERT_EQ(unheld->map().centre(), centre);
    EXPECT_EQ(unheld->counters().fls_frames_replayed, 0);
    int differ_early = 0, differ_unheld = 0, touched_late = 0, touched_unheld = 0;
    for (std::size_t i = 0; i < late->map().size(); ++i) {
        differ_early += late->map().logOdds(i) != early->map().logOdds(i);
        differ_unheld += late->map().logOdds(i) != unheld->map().logOdds(i);
        touched_late += late->map().flsTouched(i);
        touched_unheld += unheld->map().flsTouched(i);
    }
    EXPECT_EQ(differ_early, 0);
    EXPECT_GT(differ_unheld, 100);
    EXPECT_GT(touched_late, touched_unheld);
}

// UpdateConfig::fls_seabed_judged_later (docs/algorithm.md, "Frames seen before
// the seabed was known"). A pass starting 3.5 m before the box: its first FLS
// frames see the box before the detector has gathered min_seabed_echoes, so no
// seabed plane exists to call their votes above the seabed. Judged again
// against the plane found there later, they count: more above-seabed votes,
// and only there (log-odds and flags unchanged). The old rule counts none of
// those frames' votes.
TEST(Mapper, FramesSeenBeforeTheSeabedWasKnownAreJudgedAgainstTheLaterPlane) {
    test::BoxWorld world;
    auto run = [&](bool later) {
        MapperConfig cfg;
        cfg.update.fls_seabed_judged_later = later;
        auto mapper = std::make_unique<Mapper>(cfg);
        runPass(*mapper, world, 1000, -4.5);
        return mapper;
    };
    const auto judged = run(true);
    const auto unjudged = run(false);
    ASSERT_TRUE(judged->map().initialised());
    ASSERT_TRUE(unjudged->map().initialised());
    ASSERT_EQ(judged->map().centre(), unjudged->map().centre());
    EXPECT_GT(judged->counters().fls_frames_judged_later, 0);
    EXPECT_EQ(unjudged->counters().fls_frames_judged_later, 0);
    long long votes_judged = 0, votes_unjudged = 0, on_box_gained = 0, off_box_gained = 0;
    int differ = 0;
    for (std::size_t i = 0; i < judged->map().size(); ++i) {
        differ += judged->map().logOdds(i) != unjudged->map().logOdds(i) ||
                  judged->map().flags(i) != unjudged->map().flags(i);
        const int a = judged->map().flsAboveSeabedVotes(i), b = unjudged->map().flsAboveSeabedVotes(i);
        votes_judged += a;
        votes_unjudged += b;
        EXPECT_GE(a, b);
        if (a > b) {
            // Gained votes lie above the seabed, on the box's arcs.
            const Eigen::Vector3d c = judged->map().centreOf(judged->map().fromLinear(i));
            (c.z() < world.seabed - 0.15 ? on_box_gained : off_box_gained) += a - b;
        }
    }
    EXPECT_EQ(differ, 0);
    EXPECT_GT(votes_judged, votes_unjudged);
    EXPECT_GT(on_box_gained, 0);
    // The plane found later judges as one found then would: the paper variant
    // (no footprint plane) never judges again.
    MapperConfig paper;
    applyVariant(Variant::Paper, paper);
    EXPECT_FALSE(paper.update.fls_seabed_judged_later);
}

// DetectorConfig::nearest_echo_sigmas. A post 0.6 m tall stands in the PS fan,
// but the seabed, echoing across the whole fan at one range, is every ping's
// strongest bin: paper 2.1's maximum never rises. The post's weaker echo
// comes first in range, and in the tilted fan nothing but a surface above the
// seabed returns from nearer than the seabed does. The seabed itself returns
// first from the fan's steepest edge (PsGeometry::beam_width_vertical): its
// leading edge, placed on the centre line, would stand up to 0.14 m high at
// the sector's shallow end; placed on that edge, it does not rise.
TEST(Mapper, ANarrowObjectTheSeabedOutshinesIsDetectedFromItsNearerEcho) {
    auto run = [](double sigmas, double beam_width_deg, bool post) {
        MapperConfig cfg;
        cfg.detector.nearest_echo_sigmas = sigmas;
        cfg.ps.beam_width_vertical = beam_width_deg * kDeg;
        Mapper mapper(cfg);
        const double post_x = 2.0, post_top = 19.4, seabed = 20.0;
        for (int i = 0; i < 1400; ++i) {
            const int64_t t = 1000000 + i * 50000LL;
            const TimedPose nav = test::trackPose(t, -6.0 + 0.005 * i);
            mapper.addNav(nav);
            const double head = test::sectorScanHead(i);
            test::OwnedPing ping = test::blankPing(500, 10.0, t, head);
            const Eigen::Isometry3d s = sensorToWorld(nav.pose, Mounting{});
            const Eigen::Vector3d d = s.linear() * mapper.psModel().centreDirection(head);
            const Eigen::Vector3d steep = s.linear() * mapper.psModel().centreDirection(head + 1.0 * kDeg);
            auto mark = [&](double r, uint8_t strongest, uint8_t beside) {
                const int bin = static_cast<int>(std::lround(r / 10.0 * 499));
                if (bin < 1 || bin > 498) return;
                for (int b = bin - 1; b <= bin + 1; ++b) ping.bins[b] = std::max(ping.bins[b], b == bin ? strongest : beside);
            };
            const double depth = seabed - s.translation().z();
            mark(depth / steep.z(), 60, 50);  // the seabed's leading edge: the 2 deg fan's steepest rays
            mark(depth / d.z(), 240, 200);    // the seabed, across the fan
            const double r_post = (post_x - s.translation().x()) / d.x();
            const double z_post = s.translation().z() + r_post * d.z();
            if (post && r_post > 0.0 && z_post >= post_top && z_post <= seabed) mark(r_post, 70, 60);  // a few rays
            mapper.addPs(ping.view);
        }
        return mapper.counters().map_initialisations > 0 ? std::optional<Eigen::Vector3d>(mapper.map().centre())
                                                         : std::nullopt;
    };
    EXPECT_FALSE(run(0.0, 2.0, true).has_value());  // the strongest bin only (paper 2.1)
    const std::optional<Eigen::Vector3d> centre = run(4.0, 2.0, true);
    ASSERT_TRUE(centre.has_value());
    EXPECT_NEAR(centre->x(), 2.0, 0.2);  // anchored on the post
    EXPECT_NEAR(centre->y(), 0.0, 0.2);
    EXPECT_FALSE(run(4.0, 2.0, false).has_value());  // the seabed alone: nothing
    EXPECT_TRUE(run(4.0, 0.0, false).has_value());   // its leading edge on the centre line rises
}

// DetectorConfig::fls_nearer_than_seabed. A box 1 m tall lies 0.9-1.3 m beside
// a track flown at 4.5 m; the PS (here: a PS that sees only the seabed) gives
// no risen echo, but the FLS, whose fan is wider, sees the box's top from
// nearer than any ray of the beam could meet the seabed.
TEST(Mapper, AnObjectBesideThePsFanIsDetectedByTheFls) {
    auto run = [](bool fls_detects, bool box) {
        MapperConfig cfg;
        cfg.detector.fls_nearer_than_seabed = fls_detects;
        Mapper mapper(cfg);
        test::BoxWorld world, seabed_only;
        world.box_min = Eigen::Vector3d(-0.3, 0.9, 19.0);
        world.box_max = Eigen::Vector3d(0.3, 1.3, 20.0);
        seabed_only.box_min.x() += 1000.0;
        seabed_only.box_max.x() += 1000.0;
        if (!box) world = seabed_only;
        for (int i = 0; i < 1400; ++i) {
            const int64_t t = 1000000 + i * 50000LL;
            const TimedPose nav = test::poseAt(t, -6.0 + 0.005 * i, 0.0, 20.0 - 4.5);
            mapper.addNav(nav);
            const double head = test::sectorScanHead(i);
            auto ping = test::simulatePing(seabed_only, mapper.psModel(), nav.pose, t, head);
            mapper.addPs(ping.view);
            if (i % 4 == 0) {
                auto frame = test::simulateFrame(world, mapper.config().fls, mapper.flsModel(), nav.pose, t);
                mapper.addFls(frame.view);
            }
        }
        return mapper.counters().map_initialisations > 0 ? std::optional<Eigen::Vector3d>(mapper.map().centre())
                                                         : std::nullopt;
    };
    EXPECT_FALSE(run(false, true).has_value());  // the PS alone (the default)
    const std::optional<Eigen::Vector3d> centre = run(true, true);
    ASSERT_TRUE(centre.has_value());
    EXPECT_LT((centre->head<2>() - Eigen::Vector2d(0.0, 1.1)).norm(), 1.0);  // anchored on the box
    EXPECT_FALSE(run(true, false).has_value());  // the seabed alone: nothing
}
