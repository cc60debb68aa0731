// Paper 2.1: before any map exists, each PS ping's strongest echo becomes a
// world point. The seabed under the vehicle is a plane fitted to the recent
// seabed echoes nearby; an echo standing clearly above it is "risen"; where
// risen echoes cluster, an object is declared and the map is initialised there.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <optional>
#include <vector>

#include "sonarfusion/config.hpp"
#include "sonarfusion/seabed_fit.hpp"
#include "sonarfusion/state_codec.hpp"

namespace sonarfusion {


class ObjectDetector {
public:
    explicit ObjectDetector(const DetectorConfig& cfg);  // rings allocated here

    // Feeds one echo point (NED). Returns true on each echo that declares an
    // object (detection() is then its position). The detector stays armed: the
    // declaring cluster's echoes are spent and later clusters declare again.
    // deeper_by (m, >= 0): how much deeper than p the same echo may lie
    // within its beam's thickness (DetectorConfig::rise_from_deepest_in_beam).
    bool addEchoPoint(const Eigen::Vector3d& p, double deeper_by = 0.0);
    // The same for a ping whose nearest echo `nearest` lies nearer than its
    // strongest `p` (DetectorConfig::nearest_echo_sigmas): when p does not
    // rise, nearest is judged against the plane p was judged against and, if
    // it rises, is the ping's risen echo; it never enters the seabed's fits.
    // (nearest is placed on the fan's steepest edge already: no spread.)
    bool addEchoPoint(const Eigen::Vector3d& p, const Eigen::Vector3d& nearest, double deeper_by = 0.0);
    // A ping with no strongest echo (none above min_peak_intensity): its
    // nearest echo counts only if it rises above the plane around it.
    bool addNearestEcho(const Eigen::Vector3d& nearest);
    // An echo another sensor already knows stands above the seabed (an FLS
    // return from nearer than the seabed, DetectorConfig::fls_nearer_than_seabed):
    // it joins the risen echoes as it is. True when it declares an object.
    bool addRisenEcho(const Eigen::Vector3d& p);
    // An FLS shadow's seabed point (DetectorConfig::fls_shadow_false_alarm):
    // kept in a ring of its own, and fls_shadow_min_frames of them within
    // cluster_radius declare an object at their mean. True when it declares.
    bool addShadow(const Eigen::Vector3d& p);
    void reset();
    void saveState(StateWriter& w) const;
    [[nodiscard]] bool loadState(StateReader& r);

    [[nodiscard]] bool detected() const { return detection_.has_value(); }
    [[nodiscard]] int64_t detections() const { return detections_; }
    // Mean position of the risen echoes of the cluster that declared the latest object.
    [[nodiscard]] const std::optional<Eigen::Vector3d>& detection() const { return detection_; }
    // Seabed plane around `xy` from the seabed echoes within seabed_radius;
    // nothing until min_seabed_echoes lie there.
    [[nodiscard]] std::optional<SeabedFit> seabedAt(const Eigen::Vector2d& xy) const;
    // The seabed plane around the newest echo (where the PS looks now), fitted
    // on the first call after each echo and kept until the next: a pure
    // function of the echo rings, so a restored checkpoint gives the same.
    [[nodiscard]] const std::optional<SeabedFit>& seabedAtNewestEcho() const;
    // The seabed plane around where the ray origin + t direction (NED, t > 0)
    // meets it, for a sensor looking along that ray (the FLS boresight): the
    // plane around the newest echo (else under the origin) places the meeting
    // point, the plane is fitted there, and where too few echoes lie there the
    // placing plane stands. Both fits start from the echoes' lower envelope
    // (Trim::LowerEnvelope), so object echoes taken as seabed before any plane
    // existed do not lift it. Nothing until some fit exists.
    [[nodiscard]] std::optional<SeabedFit> seabedAlongRay(const Eigen::Vector3d& origin,
                                                          const Eigen::Vector3d& direction) const;
    // Seabed depth (NED z, m) under the newest echo; nothing until the fit exists.
    [[nodiscard]] std::optional<double> baseline() const;
    // The rise an echo must exceed above the fitted seabed (m).
    [[nodiscard]] double riseThreshold(const SeabedFit& fit) const;
    // Whether echo p stands above `plane` by more than riseThreshold(plane)
    // and, with rise_from_deepest_in_beam, p + deeper_by down still by min_rise.
    [[nodiscard]] bool risesAbove(const Eigen::Vector3d& p, const SeabedFit& plane, double deeper_by = 0.0) const;
    // Whether a held ping's echo p (DetectorConfig::replay_risen_pings_whole)
    // rises: against the plane around it or, where none stands (the object's
    // own echoes, judged risen, leave the disc of a mission's first metres
    // under min_seabed_echoes), the plane the newest echo was judged against.
    [[nodiscard]] bool heldEchoRises(const Eigen::Vector3d& p, double deeper_by = 0.0) const;
    // Whether the latest declaration came from echoes taken before any seabed
    // plane stood where they lie, judged when one first did (judge_early_echoes):
    // the PS saw the object before the detector could judge it.
    [[nodiscard]] bool declaredByEarlyEchoes() const { return declared_early_; }

private:
    // How fit() trims: Rise, for judging rises (twice leave out echoes more
    // than one scatter above, then keep those within 3 scatters); LowerEnvelope,
    // for a seabed a share of whose echoes may be an object's (keep those no
    // shallower than their median, then those at or below the plane through
    // them, or with envelope_per_line and two lines in the disc each line's
    // lower half about it, then three times those within 3 scatters; nothing
    // when fewer than a quarter of min_seabed_echoes are left).
    enum class Trim { Rise, LowerEnvelope };
    // DetectorConfig::rise_trim_converges: at most this many more windows.
    static constexpr int kMaxExtraWindows = 16;
    [[nodiscard]] std::optional<SeabedFit> fit(const Eigen::Vector2d& xy, Trim trim) const;
    // The seabed echoes within seabed_radius of xy (copied to disc_), their
    // mean position and depth, and the axis across their line; what a Rise
    // fit and the LowerEnvelope fit it starts from share, computed once.
    struct Disc {
        int m = 0;
        Eigen::Vector2d centre = Eigen::Vector2d::Zero();
        double depth0 = 0.0;
        Eigen::Vector2d across = Eigen::Vector2d::UnitY();
        double u_xy = 0.0;         // xy's offset along `across` from centre
        bool other_lines = false;  // some echo lies more than cluster_radius across from xy
        // Whether p lies on xy's own line: within `radius` of it across the axis.
        [[nodiscard]] bool onOwnLine(const Eigen::Vector2d& p, double radius) const {
            return std::fabs(across.dot(p - centre) - u_xy) <= radius;
        }
    };
    [[nodiscard]] std::optional<Disc> discAt(const Eigen::Vector2d& xy) const;
    [[nodiscard]] std::optional<SeabedFit> fitDisc(const Disc& disc, Trim trim) const;
    // What a seabed-ring echo is: judged seabed; taken before any plane existed
    // where it lies (not yet judged); or found risen when judged later (then
    // kept out of every fit, as risen echoes are).
    enum class EchoState : uint8_t { Seabed, Unjudged, RisenLater };
    void addSeabed(const Eigen::Vector3d& p, EchoState state, double deeper_by);
    void addRisen(const Eigen::Vector3d& p);
    // Judges the unjudged echoes within seabed_radius of xy against `plane`
    // (DetectorConfig::judge_early_echoes); true when the risen ones declare an object.
    bool judgeEarlyEchoes(const Eigen::Vector2d& xy, const SeabedFit& plane);
    // Declares an object when enough risen echoes lie within cluster_radius of xy.
    bool declareAround(const Eigen::Vector2d& xy);
    bool addEcho(const Eigen::Vector3d& p, const Eigen::Vector3d* nearest, double deeper_by);

    DetectorConfig cfg_;
    std::vector<Eigen::Vector3d> seabed_;  // ring of seabed echoes
    std::vector<EchoState> seabed_state_;  // per slot of seabed_
    std::vector<double> seabed_deeper_by_;  // per slot of seabed_: the echo's spread down its beam
    mutable std::vector<double> residual_; // scratch for the median absolute residual
    // Scratch for the fits, seabed_capacity each (allocated once): the echoes
    // discAt found, in ring order; per echo, its residual about the first
    // cut's level plane and about the previous pass's plane; the echoes a pass keeps.
    mutable std::vector<Eigen::Vector3d> disc_;
    mutable std::vector<double> level_residual_, about_prev_;
    mutable std::vector<int> kept_;
    int seabed_count_ = 0, seabed_next_ = 0;
    std::vector<Eigen::Vector3d> risen_;   // ring of risen echoes
    int risen_count_ = 0, risen_next_ = 0;
    std::vector<Eigen::Vector3d> shadows_; // ring of FLS shadow points (risen_capacity)
    int shadow_count_ = 0, shadow_next_ = 0;
    Eigen::Vector2d last_xy_ = Eigen::Vector2d::Zero();
    std::optional<Eigen::Vector3d> detection_;
    std::optional<SeabedFit> newest_judging_plane_;  // the plane addEcho judged its newest echo against
    bool declared_early_ = false;                    // declaredByEarlyEchoes
    mutable std::optional<SeabedFit> newest_fit_;  // seabedAtNewestEcho's cache
    mutable bool newest_fit_valid_ = false;
    int64_t detections_ = 0;
};

}  // namespace sonarfusion
