// The simulator proper: scene + sensors + trajectory -> the LCM messages of
// every sequence (NAV, NAV_TRUTH when the scenario has NAV errors or motion,
// PS ping, FLS frame every Nth), in order. The sonars are ray-traced from the
// true pose; NAV carries what the navigation reports (navigation.hpp).
#pragma once

#include <functional>
#include <memory>
#include <vector>

#include <sonarfusion/fls_image_t.hpp>
#include <sonarfusion/nav_state_t.hpp>
#include <sonarfusion/ps_ping_t.hpp>

#include "fls_sim.hpp"
#include "navigation.hpp"
#include "ps_sim.hpp"
#include "scenario.hpp"
#include "scene.hpp"
#include "trajectory.hpp"

namespace sonarfusion::sim {

struct SequenceOutput {
    SequenceState state;
    nav_state_t nav;     // what the navigation reports
    bool has_truth = false;
    nav_state_t truth;   // the true pose, valid when has_truth (Scenario::publishesTruth)
    ps_ping_t ps;
    bool has_fls = false;
    fls_image_t fls;  // valid when has_fls
};

class Simulator {
public:
    explicit Simulator(const Scenario& scenario);

    [[nodiscard]] const std::vector<SequenceState>& sequences() const { return sequences_; }
    // What NAV reports for each sequence (index = sequence index).
    [[nodiscard]] const std::vector<NavReport>& navigation() const { return navigation_; }
    [[nodiscard]] const Scenario& scenario() const { return scenario_; }
    [[nodiscard]] const Scene& scene() const { return *scene_; }
    [[nodiscard]] const FlsSimulator& fls() const { return *fls_; }
    // The FLS as it is set at sequence `index` (fls.window_changes; fls() before the first).
    [[nodiscard]] const FlsSimulator& flsAt(int64_t index) const;
    [[nodiscard]] const PsSimulator& ps() const { return *ps_; }

    // All messages of one sequence; `threads` split the FLS beams.
    [[nodiscard]] SequenceOutput simulate(const SequenceState& state, int threads = 1) const;

    // Simulates the first `count` sequences (all when count < 0) with `threads`
    // workers and hands them to `sink` strictly in sequence order.
    void run(int threads, int64_t count, const std::function<void(const SequenceOutput&)>& sink) const;

private:
    [[nodiscard]] double altitudeBelow(const Pose& vehicle) const;
    [[nodiscard]] nav_state_t navMessage(const SequenceState& q, const Pose& pose, const Eigen::Vector3d& velocity,
                                         double altitude) const;
    [[nodiscard]] fls_image_t flsMessage(const SequenceState& q, const FlsSimulator& fls, const FlsImage& image) const;
    [[nodiscard]] ps_ping_t psMessage(const SequenceState& q, std::vector<uint8_t> intensity) const;

    Scenario scenario_;
    std::unique_ptr<Scene> scene_;
    std::unique_ptr<FlsSimulator> fls_;
    std::vector<std::unique_ptr<FlsSimulator>> fls_windows_;  // one per fls.window_changes entry
    std::unique_ptr<PsSimulator> ps_;
    std::vector<SequenceState> sequences_;
    std::vector<NavReport> navigation_;
};

}  // namespace sonarfusion::sim
