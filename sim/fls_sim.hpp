// Forward-looking sonar: per beam, a grid of rays over the beam's azimuth
// width and the full vertical aperture; echoes binned by range into a column
// of the image (row 0 farthest, column 0 port-most, as the mapper expects).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "echo_model.hpp"
#include "scenario.hpp"
#include "scene.hpp"
#include "sonarfusion/fls_model.hpp"
#include "sonarfusion/pose.hpp"

namespace sonarfusion::sim {

// Level of a flat sand seabed seen by the default DIDSON at 3 m altitude lands
// near 200 counts with this gain (calibrated with sf-sim-bench --calibrate).
constexpr double kFlsBaseGainDb = 48.0;

struct FlsImage {
    int rows = 0, cols = 0;
    std::vector<uint8_t> data;  // rows x cols, row-major, row 0 farthest
    [[nodiscard]] uint8_t at(int row, int col) const { return data[static_cast<std::size_t>(row) * cols + col]; }
};

class FlsSimulator {
public:
    // `level_scale` multiplies the echo energy per range bin: a window change
    // keeps the rows, so each bin spans a different range, and a real sonar's
    // pixel level does not depend on the bin length (Simulator passes the span ratio).
    FlsSimulator(const Scene& scene, const Scenario& scenario, double level_scale = 1.0);

    // One frame at a vehicle pose. `threads` workers split the beams; the
    // bytes do not depend on the thread count.
    [[nodiscard]] FlsImage render(const Pose& vehicle, int64_t sequence, int threads = 1) const;

    [[nodiscard]] const FlsModel& model() const { return model_; }
    [[nodiscard]] int64_t raysPerFrame() const { return static_cast<int64_t>(rays_per_beam_) * model_.cols(); }
    // Row index of each entry of the binner is the image row.
    [[nodiscard]] const RangeBinner& binner() const { return binner_; }

private:
    void renderBeam(int col, const Eigen::Isometry3d& world_from_sensor, int64_t sequence, FlsImage& image) const;

    const Scene& scene_;
    FlsModel model_;
    Mounting mount_;
    NoiseSpec noise_;
    uint64_t seed_;
    RangeBinner binner_;
    ReceiverChain chain_;
    int rays_per_beam_;
    std::vector<Eigen::Vector3f> directions_;  // sensor frame, beams x rays_per_beam
};

}  // namespace sonarfusion::sim
