#include "sonarfusion/object_detector.hpp"

#include "sonarfusion/robust_scatter.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace sonarfusion {

ObjectDetector::ObjectDetector(const DetectorConfig& cfg) : cfg_(cfg) {
    if (!(cfg.seabed_radius > 0.0) || cfg.seabed_capacity < 3 || cfg.min_seabed_echoes < 3 ||
        cfg.min_seabed_echoes > cfg.seabed_capacity || !(cfg.min_rise > 0.0) || !(cfg.rise_sigmas >= 0.0) ||
        !(cfg.cluster_radius > 0.0) || cfg.min_risen_echoes < 1 || cfg.risen_capacity < cfg.min_risen_echoes ||
        !std::isfinite(cfg.seabed_radius + cfg.min_rise + cfg.rise_sigmas + cfg.cluster_radius) ||
        cfg.seabed_capacity > (1 << 20) || cfg.risen_capacity > (1 << 16))
        throw std::invalid_argument(
            "detector: need seabed_radius, min_rise, cluster_radius > 0, rise_sigmas >= 0, "
            "3 <= min_seabed_echoes <= seabed_capacity <= 2^20, 1 <= min_risen_echoes <= risen_capacity <= 2^16");
    seabed_.assign(cfg.seabed_capacity, Eigen::Vector3d::Zero());
    seabed_state_.assign(cfg.seabed_capacity, EchoState::Seabed);
    seabed_deeper_by_.assign(cfg.seabed_capacity, 0.0);
    residual_.assign(cfg.seabed_capacity, 0.0);
    disc_.assign(cfg.seabed_capacity, Eigen::Vector3d::Zero());
    level_residual_.assign(cfg.seabed_capacity, 0.0);
    about_prev_.assign(cfg.seabed_capacity, 0.0);
    kept_.assign(cfg.seabed_capacity, 0);
    risen_.assign(cfg.risen_capacity, Eigen::Vector3d::Zero());
    shadows_.assign(cfg.risen_capacity, Eigen::Vector3d::Zero());
}

void ObjectDetector::reset() {
    seabed_count_ = seabed_next_ = 0;
    std::fill(seabed_state_.begin(), seabed_state_.end(), EchoState::Seabed);
    std::fill(seabed_deeper_by_.begin(), seabed_deeper_by_.end(), 0.0);
    risen_count_ = risen_next_ = 0;
    shadow_count_ = shadow_next_ = 0;
    last_xy_.setZero();
    detection_.reset();
    detections_ = 0;
    newest_judging_plane_.reset();
    declared_early_ = false;
    newest_fit_valid_ = false;
}

const std::optional<SeabedFit>& ObjectDetector::seabedAtNewestEcho() const {
    if (!newest_fit_valid_) {
        newest_fit_ = seabed_count_ > 0 ? seabedAt(last_xy_) : std::nullopt;
        newest_fit_valid_ = true;
    }
    return newest_fit_;
}

// Least-squares plane through the seabed echoes within seabed_radius of xy. The
// gradient is lightly regularised, so echoes along one line (a straight pass
// sees the seabed mostly along its centre line) give a level cross-slope
// instead of a wild one. With reject_outliers the fit is trimmed toward the
// seabed's lower envelope, since objects only ever stand above it: twice, the
// echoes more than one scatter above the previous plane are left out (an
// object seen before the seabed was known, when a pass starts close to it),
// then a last fit keeps the echoes within 3 scatters of that plane on either
// side, so a slope is not flattened. The scatter is 1.4826 x the median
// absolute residual, over both sides: a rough seabed's crests return the
// strongest echoes, and the residuals below the plane alone understate it.
// min_seabed_echoes (more than one head sweep) keeps a first sweep that is
// mostly object from being judged alone.
std::optional<SeabedFit> ObjectDetector::fit(const Eigen::Vector2d& xy, Trim trim) const {
    const std::optional<Disc> disc = discAt(xy);
    if (!disc) return std::nullopt;
    return fitDisc(*disc, trim);
}

// The echoes within seabed_radius of xy (copied to disc_, in ring
// order, so every later pass sums as a pass over the ring would) and what
// both trims need of them; nothing when they are too few or, with
// seabed_across_lines, when too few lie across from xy.
std::optional<ObjectDetector::Disc> ObjectDetector::discAt(const Eigen::Vector2d& xy) const {
    const double r2 = cfg_.seabed_radius * cfg_.seabed_radius;
    Disc d;
    for (int i = 0; i < seabed_count_; ++i)
        if (seabed_state_[i] != EchoState::RisenLater && (seabed_[i].head<2>() - xy).squaredNorm() <= r2) {
            disc_[d.m++] = seabed_[i];
            d.centre += seabed_[i].head<2>();
            d.depth0 += seabed_[i].z();
        }
    if (d.m < cfg_.min_seabed_echoes) return std::nullopt;
    d.centre /= d.m;
    d.depth0 /= d.m;
    const Eigen::Vector3d* const begin = disc_.data();
    const Eigen::Vector3d* const end = begin + d.m;
    // DetectorConfig::seabed_across_lines. The PS places its echoes on the
    // track line, so a line flown beside an earlier one lies across from every
    // echo of that line, where the line's plane is an extrapolation whose tilt
    // across no echo measured (the ridge below levels it). So a plane judges
    // only where a quarter of min_seabed_echoes (as the trims below keep) lie
    // within cluster_radius of xy across the echoes' long axis: over that
    // distance a 5 deg slope moves the seabed 4 cm, under half of min_rise.
    // Elsewhere there is no plane yet, and echoes wait as at a mission's start
    // (judge_early_echoes).
    if (cfg_.seabed_across_lines) {
        // The line's direction: the long axis of the echoes within
        // cluster_radius of xy (the eigenvector of the smaller eigenvalue is
        // across it). Over the whole disc two lines of unequal length (a new
        // one just begun beside an old one) tilt the axis off both.
        const double c2 = cfg_.cluster_radius * cfg_.cluster_radius;
        Eigen::Matrix2d near_spread = Eigen::Matrix2d::Zero(), spread = Eigen::Matrix2d::Zero();
        Eigen::Vector2d near_sum = Eigen::Vector2d::Zero();
        int near = 0;
        for (const Eigen::Vector3d* i = begin; i != end; ++i) {
            const Eigen::Vector2d dc = i->head<2>() - d.centre;
            spread += dc * dc.transpose();
            if ((i->head<2>() - xy).squaredNorm() <= c2) {
                near_sum += i->head<2>();
                ++near;
            }
        }
        if (near >= 3) {
            const Eigen::Vector2d near_centre = near_sum / near;
            for (const Eigen::Vector3d* i = begin; i != end; ++i)
                if ((i->head<2>() - xy).squaredNorm() <= c2) {
                    const Eigen::Vector2d dn = i->head<2>() - near_centre;
                    near_spread += dn * dn.transpose();
                }
        }
        // Near echoes that do not lie along a line (a sweep zig-zagging
        // across the track, widths at least half their lengths) say nothing
        // of its direction: then the whole disc's axis.
        const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> local(near_spread);
        const bool along_a_line = near >= 3 && local.eigenvalues()(0) < 0.25 * local.eigenvalues()(1);
        d.across = along_a_line
                       ? Eigen::Vector2d(local.eigenvectors().col(0))
                       : Eigen::Vector2d(Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(spread).eigenvectors().col(0));
        d.u_xy = d.across.dot(xy - d.centre);
        int beside = 0;
        for (const Eigen::Vector3d* i = begin; i != end; ++i)
            beside += d.onOwnLine(i->head<2>(), cfg_.cluster_radius);
        if (beside < std::max(3, cfg_.min_seabed_echoes / 4)) return std::nullopt;
        d.other_lines = beside < d.m;
    }
    return d;
}

std::optional<SeabedFit> ObjectDetector::fitDisc(const Disc& disc, Trim trim) const {
    const bool lower = trim == Trim::LowerEnvelope;
    // The disc's echoes (discAt gathered them, in ring order); k below is an
    // echo's place among them. Every sum runs over the echoes a pass keeps in
    // that order, as a pass over the ring would.
    const Eigen::Vector3d* const echo = disc_.data();
    const int m = disc.m;
    const Eigen::Vector2d& centre = disc.centre;
    const Eigen::Vector2d& across = disc.across;
    const double depth0 = disc.depth0;
    // LowerEnvelope starts from the echoes no shallower than their median
    // about a plane level along the track (a level cut, which a plane tilted
    // onto an object on one side cannot fool: a first pass, seabed behind,
    // object ahead). With seabed_across_lines that plane is tilted across the
    // echoes' long axis as the echoes there lie: on a seabed sloping across
    // two lines a level cut kept only the downhill one. One line has no spread
    // across itself, and the ridge leaves that tilt level: the level cut.
    double median_residual = 0.0, tilt = 0.0;
    // DetectorConfig::envelope_per_line: the second halving per line, where
    // the disc holds more than xy's own.
    const bool per_line = lower && cfg_.seabed_across_lines && cfg_.envelope_per_line && disc.other_lines;
    double second_beside = 0.0, second_others = 0.0;  // the second cut's medians, per group
    auto onOwnLine = [&](int k) { return disc.onOwnLine(echo[k].head<2>(), cfg_.cluster_radius); };
    enum class Group { All, Beside, Others };
    // The median of value(k) (a double, or an optional one: nothing leaves k
    // out) over the group's echoes; 0 for an empty group.
    auto groupMedian = [&](Group g, auto value) {
        std::size_t n = 0;
        for (int k = 0; k < m; ++k) {
            if (g != Group::All && onOwnLine(k) != (g == Group::Beside)) continue;
            const std::optional<double> v = value(k);
            if (v) residual_[n++] = *v;
        }
        return n > 0 ? medianInPlace(residual_, n) : 0.0;
    };
    if (lower) {
        if (cfg_.seabed_across_lines) {
            double suu = 1e-3 * m, suz = 0.0;  // the plane fits' ridge: (3 cm)^2 per echo
            for (int k = 0; k < m; ++k) {
                const double u = across.dot(echo[k].head<2>() - centre);
                suu += u * u;
                suz += u * (echo[k].z() - depth0);
            }
            tilt = suz / suu;
        }
        // Each echo's residual about the plane the first cut is made from,
        // once: the median, and the cut itself in the passes after it.
        for (int k = 0; k < m; ++k)
            level_residual_[k] = echo[k].z() - depth0 - tilt * across.dot(echo[k].head<2>() - centre);
        median_residual = groupMedian(Group::All, [&](int k) { return level_residual_[k]; });
    }
    auto firstCut = [&](int k) { return level_residual_[k] >= median_residual; };
    SeabedFit f;
    const int passes = lower ? 6 : 4;
    int first_pass = 0;
    // DetectorConfig::rise_from_lower_envelope: where the lower envelope gives
    // a plane, the rise trim keeps only its last pass (the echoes within 3
    // scatters either side), so a rough seabed seen mostly on its crests gets
    // back its two-sided scatter; its first passes, which trim from the plane
    // through every echo, are what object echoes taken before any plane lift.
    if (!lower && cfg_.rise_from_lower_envelope) {
        if (std::optional<SeabedFit> start = fitDisc(disc, Trim::LowerEnvelope)) {
            f = *start;
            first_pass = passes - 1;
        }
    }
    // DetectorConfig::rise_trim_converges: the rise trim's last window (the
    // echoes within 3 scatters of the plane, either side) repeats until it
    // keeps the same echoes. Each earlier cut (the median, the lower half, one
    // side) keeps echoes by their depth, which flattens the plane's slope and
    // narrows its scatter; one window about that plane does not undo it.
    const int last_stage = passes - 1;
    const int max_passes = (!lower && cfg_.rise_trim_converges) ? passes + kMaxExtraWindows : passes;
    for (int stage_pass = first_pass; stage_pass < max_passes; ++stage_pass) {
        const int pass = std::min(stage_pass, last_stage);
        const SeabedFit prev = f;
        // A scatter under a millimetre is rounding, not the seabed's: echoes
        // exactly on a plane must all stay in the trim's window.
        const double scatter = std::max(prev.rms, 1e-3);
        // Each echo's residual about the previous pass's plane, once (NED:
        // negative is above).
        if (pass > 0)
            for (int k = 0; k < m; ++k) about_prev_[k] = echo[k].z() - prev.depthAt(echo[k].head<2>());
        if (per_line && pass == 2) {
            // Each group's median residual about the plane of the first cut,
            // over that group's echoes the first cut kept.
            auto about_prev = [&](int k) {
                return firstCut(k) ? std::optional<double>(about_prev_[k]) : std::nullopt;
            };
            second_beside = groupMedian(Group::Beside, about_prev);
            second_others = groupMedian(Group::Others, about_prev);
        }
        auto use = [&](int k) {
            if (pass == 0) return true;
            const double residual = about_prev_[k];
            if (lower) {
                if (pass == 1) return firstCut(k);
                if (pass == 2) {  // then the lower half about that plane
                    if (!per_line) return residual >= 0.0;
                    return firstCut(k) && residual >= (onOwnLine(k) ? second_beside : second_others);
                }
                return std::fabs(residual) <= 3.0 * scatter;
            }
            return pass < passes - 1 ? residual >= -scatter : std::fabs(residual) <= 3.0 * scatter;
        };
        // The echoes this pass keeps, decided once; the sums below read the list.
        int n = 0;
        for (int k = 0; k < m; ++k)
            if (use(k)) kept_[n++] = k;
        Eigen::Vector2d sum_xy = Eigen::Vector2d::Zero();
        double sum_z = 0.0;
        for (int j = 0; j < n; ++j) {
            sum_xy += echo[kept_[j]].head<2>();
            sum_z += echo[kept_[j]].z();
        }
        if (lower && pass > 0) {
            // Two halvings keep a quarter of a clean seabed; fewer, and what is
            // left is not the seabed's to judge by (the first plane, all echoes
            // included, is what this trim exists to avoid).
            if (n < std::max(3, cfg_.min_seabed_echoes / 4)) return std::nullopt;
        } else if (n < cfg_.min_seabed_echoes) {
            return pass == 0 ? std::nullopt : std::optional<SeabedFit>(prev);
        }
        const Eigen::Vector2d c = sum_xy / n;
        const double zc = sum_z / n;
        Eigen::Matrix2d a = Eigen::Matrix2d::Identity() * (1e-3 * n);  // ridge: (3 cm)^2 per echo
        Eigen::Vector2d b = Eigen::Vector2d::Zero();
        for (int j = 0; j < n; ++j) {
            const Eigen::Vector3d& p = echo[kept_[j]];
            const Eigen::Vector2d d = p.head<2>() - c;
            a += d * d.transpose();
            b += d * (p.z() - zc);
        }
        f.centre = c;
        f.depth = zc;
        f.gradient = a.ldlt().solve(b);
        f.echoes = n;
        // Robust scatter of the echoes in this fit about it (not about their
        // median: the plane is the model, its residuals' centre is zero).
        for (int j = 0; j < n; ++j) {
            const Eigen::Vector3d& p = echo[kept_[j]];
            residual_[j] = p.z() - f.depthAt(p.head<2>());
        }
        f.rms = robustSigmaInPlace(residual_, static_cast<std::size_t>(n), 0.0);
        // The same echoes give the same plane: a window that changed nothing is the fixed point.
        if (stage_pass > last_stage && f.echoes == prev.echoes && f.depth == prev.depth &&
            f.gradient == prev.gradient && f.rms == prev.rms)
            break;
    }
    return f;
}

std::optional<SeabedFit> ObjectDetector::seabedAt(const Eigen::Vector2d& xy) const { return fit(xy, Trim::Rise); }

std::optional<SeabedFit> ObjectDetector::seabedAlongRay(const Eigen::Vector3d& origin,
                                                        const Eigen::Vector3d& direction) const {
    std::optional<SeabedFit> placing = fit(last_xy_, Trim::LowerEnvelope);
    if (!placing) placing = fit(origin.head<2>(), Trim::LowerEnvelope);
    if (!placing) return std::nullopt;
    const double descent = placing->closingRate(direction);
    const double depth_below = placing->depthAt(origin.head<2>()) - origin.z();
    if (!(descent > 1e-6) || !(depth_below > 0.0)) return placing;
    const Eigen::Vector2d xy = origin.head<2>() + (depth_below / descent) * direction.head<2>();
    std::optional<SeabedFit> there = fit(xy, Trim::LowerEnvelope);
    return there ? there : placing;
}

std::optional<double> ObjectDetector::baseline() const {
    const std::optional<SeabedFit> f = seabedAt(last_xy_);
    if (!f) return std::nullopt;
    return f->depthAt(last_xy_);
}

double ObjectDetector::riseThreshold(const SeabedFit& fit) const {
    return std::max(cfg_.min_rise, cfg_.rise_sigmas * fit.rms);
}

bool ObjectDetector::risesAbove(const Eigen::Vector3d& p, const SeabedFit& plane, double deeper_by) const {
    // NED: up is -z, so an echo that rose above the seabed has a smaller z.
    const double seabed = plane.depthAt(p.head<2>());
    if (!(p.z() < seabed - riseThreshold(plane))) return false;
    // rise_from_deepest_in_beam: risen from wherever in the fan's thickness it came.
    return !cfg_.rise_from_deepest_in_beam || p.z() + std::max(0.0, deeper_by) < seabed - cfg_.min_rise;
}

bool ObjectDetector::heldEchoRises(const Eigen::Vector3d& p, double deeper_by) const {
    if (!p.allFinite()) return false;
    const std::optional<SeabedFit> around = seabedAt(p.head<2>());
    const std::optional<SeabedFit>& plane = around ? around : newest_judging_plane_;
    return plane && risesAbove(p, *plane, deeper_by);
}

void ObjectDetector::addSeabed(const Eigen::Vector3d& p, EchoState state, double deeper_by) {
    seabed_[seabed_next_] = p;
    seabed_state_[seabed_next_] = state;
    seabed_deeper_by_[seabed_next_] = std::isfinite(deeper_by) ? std::max(0.0, deeper_by) : 0.0;
    seabed_next_ = (seabed_next_ + 1) % cfg_.seabed_capacity;
    if (seabed_count_ < cfg_.seabed_capacity) ++seabed_count_;
}

void ObjectDetector::addRisen(const Eigen::Vector3d& p) {
    risen_[risen_next_] = p;
    risen_next_ = (risen_next_ + 1) % cfg_.risen_capacity;
    if (risen_count_ < cfg_.risen_capacity) ++risen_count_;
}

bool ObjectDetector::declareAround(const Eigen::Vector2d& xy) {
    // An object is where risen echoes gather: enough of them within
    // cluster_radius of this one. Isolated spikes (speckle, fish) never gather.
    const double c2 = cfg_.cluster_radius * cfg_.cluster_radius;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    int n = 0;
    for (int i = 0; i < risen_count_; ++i)
        if ((risen_[i].head<2>() - xy).squaredNorm() <= c2) {
            sum += risen_[i];
            ++n;
        }
    if (n < cfg_.min_risen_echoes) return false;
    detection_ = sum / n;
    ++detections_;
    declared_early_ = false;  // judgeEarlyEchoes sets it for its own declarations
    // The detector stays armed (survey mode): the echoes of this cluster are
    // spent, so the same object declares again only from fresh echoes.
    int kept = 0;
    for (int i = 0; i < risen_count_; ++i)
        if ((risen_[i].head<2>() - xy).squaredNorm() > c2) risen_[kept++] = risen_[i];
    risen_count_ = kept;
    risen_next_ = kept % cfg_.risen_capacity;
    return true;
}

// Echoes taken while no plane existed where they lie went in as seabed, object
// echoes among them when the PS's first sweeps fall on an object (a mission
// starting close to it). The first plane there judges them as it would have
// judged them on arrival; the plane is fitted over seabed_radius, so it holds
// for every echo within it.
bool ObjectDetector::judgeEarlyEchoes(const Eigen::Vector2d& xy, const SeabedFit& plane) {
    const double r2 = cfg_.seabed_radius * cfg_.seabed_radius;
    int risen_now = 0;
    for (int i = 0; i < seabed_count_; ++i) {
        if (seabed_state_[i] != EchoState::Unjudged || (seabed_[i].head<2>() - xy).squaredNorm() > r2) continue;
        // DetectorConfig::judge_early_echoes_by_tighter_plane: also the plane fitted
        // where the echo lies, and of the two the one with the smaller
        // scatter. Early echoes are in both fits, and an object's among them
        // lift a plane and widen its scatter (at one end of the disc they
        // tilt it, at its centre the rise trim's window can grow to hold
        // them): the tighter plane is the one they lifted less.
        std::optional<SeabedFit> own;
        if (cfg_.judge_early_echoes_by_tighter_plane) own = seabedAt(seabed_[i].head<2>());
        const SeabedFit& judge = own && own->rms < plane.rms ? *own : plane;
        const bool risen = risesAbove(seabed_[i], judge, seabed_deeper_by_[i]);
        seabed_state_[i] = risen ? EchoState::RisenLater : EchoState::Seabed;
        if (!risen) continue;
        addRisen(seabed_[i]);
        ++risen_now;
    }
    if (risen_now == 0) return false;
    newest_fit_valid_ = false;  // the seabed's fits no longer hold these echoes
    // Newest first: the ring's last risen_now entries are the echoes just risen.
    for (int k = 0; k < std::min(risen_now, risen_count_); ++k) {
        const int i = ((risen_next_ - 1 - k) % cfg_.risen_capacity + cfg_.risen_capacity) % cfg_.risen_capacity;
        if (declareAround(risen_[i].head<2>())) {
            declared_early_ = true;
            return true;
        }
    }
    return false;
}

bool ObjectDetector::addEchoPoint(const Eigen::Vector3d& p, double deeper_by) { return addEcho(p, nullptr, deeper_by); }

bool ObjectDetector::addEchoPoint(const Eigen::Vector3d& p, const Eigen::Vector3d& nearest, double deeper_by) {
    return addEcho(p, nearest.allFinite() ? &nearest : nullptr, deeper_by);
}

bool ObjectDetector::addNearestEcho(const Eigen::Vector3d& nearest) {
    if (!nearest.allFinite()) return false;
    const std::optional<SeabedFit> seabed = seabedAt(nearest.head<2>());
    return seabed && risesAbove(nearest, *seabed) && addRisenEcho(nearest);
}

bool ObjectDetector::addRisenEcho(const Eigen::Vector3d& p) {
    if (!p.allFinite()) return false;
    addRisen(p);
    return declareAround(p.head<2>());
}

bool ObjectDetector::addShadow(const Eigen::Vector3d& p) {
    if (!p.allFinite()) return false;
    const int cap = static_cast<int>(shadows_.size());
    shadows_[shadow_next_] = p;
    shadow_next_ = (shadow_next_ + 1) % cap;
    if (shadow_count_ < cap) ++shadow_count_;
    const double c2 = cfg_.cluster_radius * cfg_.cluster_radius;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    int n = 0;
    for (int i = 0; i < shadow_count_; ++i)
        if ((shadows_[i].head<2>() - p.head<2>()).squaredNorm() <= c2) {
            sum += shadows_[i];
            ++n;
        }
    if (n < cfg_.fls_shadow_min_frames) return false;
    detection_ = sum / n;
    ++detections_;
    declared_early_ = false;  // a shadow, not echoes taken before any plane
    // Spent, as a risen echo cluster is: the same shadow declares again only
    // from fresh frames.
    int kept = 0;
    for (int i = 0; i < shadow_count_; ++i)
        if ((shadows_[i].head<2>() - p.head<2>()).squaredNorm() > c2) shadows_[kept++] = shadows_[i];
    shadow_count_ = kept;
    shadow_next_ = kept % cap;
    return true;
}

bool ObjectDetector::addEcho(const Eigen::Vector3d& p, const Eigen::Vector3d* nearest, double deeper_by) {
    if (!std::isfinite(deeper_by)) deeper_by = 0.0;
    if (!p.allFinite()) return false;
    const Eigen::Vector2d xy = p.head<2>();
    last_xy_ = xy;
    newest_fit_valid_ = false;
    const std::optional<SeabedFit> seabed = seabedAt(xy);
    if (!seabed) {
        addSeabed(p, EchoState::Unjudged, deeper_by);
        return false;
    }
    newest_judging_plane_ = seabed;
    const bool early = cfg_.judge_early_echoes && judgeEarlyEchoes(xy, *seabed);
    if (!risesAbove(p, *seabed, deeper_by)) {
        // A seabed echo (risen echoes never enter the fit, so an object cannot
        // drag the seabed up to itself).
        addSeabed(p, EchoState::Seabed, deeper_by);
        if (nearest == nullptr || !risesAbove(*nearest, *seabed)) return early;
        // The strongest echo was the seabed's; a nearer one above it is an
        // object the seabed outshone (one risen echo per ping, as before).
        addRisen(*nearest);
        return early || declareAround(nearest->head<2>());
    }
    addRisen(p);
    // One declaration per echo: a cluster this echo completes declares with the next.
    return early || declareAround(xy);
}

namespace {
void saveRing(StateWriter& w, const std::vector<Eigen::Vector3d>& ring, int count, int next) {
    w.pod(static_cast<uint64_t>(ring.size()));
    w.pod(count);
    w.pod(next);
    for (const Eigen::Vector3d& p : ring)
        for (int i = 0; i < 3; ++i) w.pod(p[i]);
}
bool loadRing(StateReader& r, std::vector<Eigen::Vector3d>& ring, int& count, int& next) {
    int c = 0, n = 0;
    if (!r.expect(ring.size()) || !r.pod(c) || !r.pod(n)) return false;
    const int cap = static_cast<int>(ring.size());
    if (c < 0 || c > cap || n < 0 || n >= std::max(cap, 1)) return false;
    for (Eigen::Vector3d& p : ring)
        for (int i = 0; i < 3; ++i)
            if (!r.pod(p[i])) return false;
    count = c, next = n;
    return true;
}
}  // namespace

void ObjectDetector::saveState(StateWriter& w) const {
    saveRing(w, seabed_, seabed_count_, seabed_next_);
    for (EchoState e : seabed_state_) w.pod(static_cast<uint8_t>(e));
    for (double s : seabed_deeper_by_) w.pod(s);
    saveRing(w, risen_, risen_count_, risen_next_);
    saveRing(w, shadows_, shadow_count_, shadow_next_);
    w.pod(last_xy_.x());
    w.pod(last_xy_.y());
    w.pod(static_cast<uint8_t>(detection_.has_value()));
    const Eigen::Vector3d d = detection_.value_or(Eigen::Vector3d::Zero());
    for (int i = 0; i < 3; ++i) w.pod(d[i]);
    w.pod(detections_);
    w.pod(static_cast<uint8_t>(newest_judging_plane_.has_value()));
    const SeabedFit f = newest_judging_plane_.value_or(SeabedFit{});
    for (double v : {f.centre.x(), f.centre.y(), f.depth, f.gradient.x(), f.gradient.y(), f.rms}) w.pod(v);
    w.pod(f.echoes);
    w.pod(static_cast<uint8_t>(declared_early_));
}

bool ObjectDetector::loadState(StateReader& r) {
    uint8_t has = 0;
    Eigen::Vector3d d;
    if (!loadRing(r, seabed_, seabed_count_, seabed_next_)) return false;
    for (EchoState& e : seabed_state_) {
        uint8_t v = 0;
        if (!r.pod(v) || v > static_cast<uint8_t>(EchoState::RisenLater)) return false;
        e = static_cast<EchoState>(v);
    }
    for (double& s : seabed_deeper_by_)
        if (!r.pod(s) || !std::isfinite(s) || s < 0.0) return false;
    if (!loadRing(r, risen_, risen_count_, risen_next_) || !loadRing(r, shadows_, shadow_count_, shadow_next_) ||
        !r.pod(last_xy_.x()) || !r.pod(last_xy_.y()) || !r.pod(has) || !r.pod(d[0]) || !r.pod(d[1]) || !r.pod(d[2]) ||
        !r.pod(detections_) || detections_ < 0)
        return false;
    detection_.reset();
    if (has) detection_ = d;
    uint8_t has_plane = 0;
    SeabedFit f;
    if (!r.pod(has_plane) || has_plane > 1) return false;
    for (double* v : {&f.centre.x(), &f.centre.y(), &f.depth, &f.gradient.x(), &f.gradient.y(), &f.rms})
        if (!r.pod(*v) || !std::isfinite(*v)) return false;
    uint8_t early = 0;
    if (!r.pod(f.echoes) || !r.pod(early) || early > 1) return false;
    declared_early_ = early != 0;
    newest_judging_plane_.reset();
    if (has_plane) newest_judging_plane_ = f;
    newest_fit_valid_ = false;  // recomputed from the loaded ring on demand
    return true;
}

}  // namespace sonarfusion
