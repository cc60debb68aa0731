#include "simulator.hpp"

#include <algorithm>
#include <cmath>

#include "parallel.hpp"

namespace sonarfusion::sim {

Simulator::Simulator(const Scenario& scenario)
    : scenario_(scenario),
      scene_(std::make_unique<Scene>(scenario.scene)),
      fls_(std::make_unique<FlsSimulator>(*scene_, scenario_)),
      ps_(std::make_unique<PsSimulator>(*scene_, scenario_)),
      sequences_(buildSequences(scenario_)),
      navigation_(reportNavigation(scenario_, sequences_)) {
    // A range window change: the same sonar (rows, beams, aperture) over
    // another window; the level per pixel stays that of the configured window.
    const double span = scenario_.fls.range_max - scenario_.fls.range_min;
    for (const FlsWindowChange& w : scenario_.fls_sim.window_changes) {
        Scenario windowed = scenario_;
        windowed.fls.range_min = w.range_min;
        windowed.fls.range_max = w.range_max;
        fls_windows_.push_back(
            std::make_unique<FlsSimulator>(*scene_, windowed, span / (w.range_max - w.range_min)));
    }
}

const FlsSimulator& Simulator::flsAt(int64_t index) const {
    const FlsSimulator* fls = fls_.get();
    const auto& changes = scenario_.fls_sim.window_changes;
    for (std::size_t i = 0; i < changes.size() && changes[i].at_sequence <= index; ++i) fls = fls_windows_[i].get();
    return *fls;
}

double Simulator::altitudeBelow(const Pose& vehicle) const {
    // An altimeter looking straight down the body z axis; -1 when nothing is below.
    const Eigen::Vector3f down = (vehicle.rotation() * Eigen::Vector3d::UnitZ()).cast<float>();
    RayHit hit;
    scene_->cast(vehicle.position.cast<float>(), &down, 1, 0.0f, 1000.0f, &hit);
    return hit.hit ? hit.range : -1.0;
}

namespace {
// The mounting fields FLS and PS messages share.
template <class Msg>
void setMounting(Msg& msg, const Mounting& m, double tilt) {
    msg.mount_xyz[0] = static_cast<float>(m.x);
    msg.mount_xyz[1] = static_cast<float>(m.y);
    msg.mount_xyz[2] = static_cast<float>(m.z);
    msg.mount_roll_yaw[0] = static_cast<float>(m.roll);
    msg.mount_roll_yaw[1] = static_cast<float>(m.yaw);
    msg.tilt = static_cast<float>(tilt);
}
}  // namespace

fls_image_t Simulator::flsMessage(const SequenceState& q, const FlsSimulator& fls, const FlsImage& image) const {
    const FlsGeometry& g = scenario_.fls;
    const Mounting& m = scenario_.fls_mount;
    const FlsModel& model = fls.model();
    fls_image_t msg;
    msg.utime = q.utime;
    msg.seq = q.index / scenario_.trajectory.fls_every;  // frames before this one
    msg.sensor_name = scenario_.fls_sim.name;
    msg.sound_speed = static_cast<float>(scenario_.fls_sim.sound_speed);
    msg.frequency_hz = static_cast<float>(scenario_.fls_sim.frequency_hz);
    setMounting(msg, m, g.tilt);
    msg.elevation_min = static_cast<float>(g.elevation_min);
    msg.elevation_max = static_cast<float>(g.elevation_max);
    msg.num_beams = model.cols();
    for (int c = 0; c < model.cols(); ++c) msg.beam_bearing.push_back(static_cast<float>(model.bearingOfColumn(c)));
    msg.num_ranges = model.rows();
    for (int r = 0; r < model.rows(); ++r) msg.row_range.push_back(static_cast<float>(model.rangeOfRow(r)));
    msg.data_size = static_cast<int32_t>(image.data.size());
    msg.data = image.data;
    return msg;
}

ps_ping_t Simulator::psMessage(const SequenceState& q, std::vector<uint8_t> intensity) const {
    const PsGeometry& g = scenario_.ps;
    const Mounting& m = scenario_.ps_mount;
    ps_ping_t msg;
    msg.utime = q.utime;
    msg.seq = q.index;
    msg.sensor_name = scenario_.ps_sim.name;
    setMounting(msg, m, g.tilt);
    msg.head_angle = static_cast<float>(q.head_angle);
    msg.fan_min = static_cast<float>(g.fan_min);
    msg.fan_max = static_cast<float>(g.fan_max);
    msg.range_min = static_cast<float>(g.range_min);
    msg.range_max = static_cast<float>(g.range_max);
    msg.num_bins = static_cast<int32_t>(intensity.size());
    msg.intensity = std::move(intensity);
    return msg;
}

namespace {
// A noise key from the pose, quantised to 1 mm and 1e-4 rad, so the speckle
// repeats exactly while the vehicle (and the PS head) hold still.
int64_t poseNoiseKey(const Pose& pose, double head_angle) {
    const double parts[] = {pose.position.x() * 1e3, pose.position.y() * 1e3, pose.position.z() * 1e3,
                            pose.roll * 1e4,         pose.pitch * 1e4,        pose.yaw * 1e4, head_angle * 1e4};
    uint64_t h = 0x9e3779b97f4a7c15ull;
    for (double v : parts) {
        const uint64_t q = static_cast<uint64_t>(static_cast<int64_t>(std::llround(v)));
        h ^= q + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
    }
    return static_cast<int64_t>(h >> 1);
}
}  // namespace

nav_state_t Simulator::navMessage(const SequenceState& q, const Pose& pose, const Eigen::Vector3d& velocity,
                                  double altitude) const {
    nav_state_t nav;
    nav.utime = q.utime;
    nav.seq = q.index;
    for (int a = 0; a < 3; ++a) {
        nav.position_ned[a] = pose.position[a];
        nav.velocity_ned[a] = velocity[a];
    }
    nav.rpy[0] = pose.roll;
    nav.rpy[1] = pose.pitch;
    nav.rpy[2] = pose.yaw;
    nav.altitude = altitude;
    return nav;
}

SequenceOutput Simulator::simulate(const SequenceState& q, int threads) const {
    SequenceOutput out;
    out.state = q;
    const std::size_t i = static_cast<std::size_t>(q.index);
    if (scenario_.navigation.enabled() && i < navigation_.size()) {
        // NAV: the lagged true pose with the navigation errors; its velocity and
        // altitude (a ray down the body z axis) are those of the lagged truth.
        const NavReport& r = navigation_[i];
        out.nav = navMessage(q, r.reported, r.truth_velocity, altitudeBelow(r.truth));
    } else {
        out.nav = navMessage(q, q.pose, q.velocity, altitudeBelow(q.pose));
    }
    if (scenario_.publishesTruth()) {
        out.has_truth = true;
        out.truth = scenario_.navigation.enabled() ? navMessage(q, q.pose, q.velocity, altitudeBelow(q.pose)) : out.nav;
    }

    const bool by_pose = scenario_.noise.follows_pose;
    const int64_t ps_key = by_pose ? poseNoiseKey(q.pose, q.head_angle) : q.index;
    const int64_t fls_key = by_pose ? poseNoiseKey(q.pose, 0.0) : q.index;
    out.ps = psMessage(q, ps_->ping(q.pose, q.head_angle, ps_key));
    out.has_fls = q.has_fls;
    if (q.has_fls) {
        const FlsSimulator& fls = flsAt(q.index);
        out.fls = flsMessage(q, fls, fls.render(q.pose, fls_key, threads));
    }
    return out;
}

void Simulator::run(int threads, int64_t count, const std::function<void(const SequenceOutput&)>& sink) const {
    threads = resolveThreads(threads);
    const int64_t total =
        count < 0 ? static_cast<int64_t>(sequences_.size()) : std::min<int64_t>(count, sequences_.size());
    // Whole sequences are spread over the threads in batches; the sink sees
    // them in order, so output bytes do not depend on the thread count.
    const int64_t batch = 8 * threads;
    std::vector<SequenceOutput> results;
    for (int64_t start = 0; start < total; start += batch) {
        const int n = static_cast<int>(std::min(batch, total - start));
        results.assign(n, SequenceOutput{});
        parallelFor(n, threads, [&](int i) { results[i] = simulate(sequences_[start + i], 1); });
        for (const SequenceOutput& r : results) sink(r);
    }
}

}  // namespace sonarfusion::sim
