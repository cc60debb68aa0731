#include "sonarfusion/fls_update.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace sonarfusion {

FlsUpdater::FlsUpdater(const FlsModel& model, const UpdateConfig& cfg, const VoxelMap& map)
    : FlsUpdater(model, cfg, map, 1, 0) {}

FlsUpdater::FlsUpdater(const FlsModel& model, const UpdateConfig& cfg, const VoxelMap& map, int geometries,
                       int max_arc_samples)
    : cfg_(cfg), increment_(static_cast<float>(logOddsFromProbability(cfg.p_occupied) * cfg.alpha_fls)),
      free_increment_(static_cast<float>(-cfg.fls_free_vote_ratio * logOddsFromProbability(cfg.p_occupied) * cfg.alpha_fls)),
      geo_(static_cast<std::size_t>(std::max(1, geometries))),
      max_arc_samples_(std::max(max_arc_samples, model.elevationSamples())),
      highlight_(cfg.fls_highlight_above_seabed ? std::max(model.rowCapacity(), model.rows()) : 0,
                 cfg.fls_highlight_above_seabed ? std::max(model.colCapacity(), model.cols()) : 0,
                 cfg.fls_highlight_half_window, cfg.fls_highlight_false_alarm) {
    if (cfg.fls_arc_spacing_voxels > 0.0) arc_spacing_ = cfg.fls_arc_spacing_voxels * map.resolution();
    buildTables(geo_[0], model);
    std::size_t world = geo_[0].sensor_direction.size();
    // The other slots: capacity for the largest geometry they may be bound to.
    const std::size_t capacity = tableSize(model.colCapacity(), model.elevationSamples(), max_arc_samples_);
    for (std::size_t i = 1; i < geo_.size(); ++i) {
        geo_[i].table_offset.reserve(static_cast<std::size_t>(max_arc_samples_) + 1);
        geo_[i].row_samples.reserve(static_cast<std::size_t>(model.rowCapacity()));
        geo_[i].sensor_direction.reserve(capacity);
        world = std::max(world, capacity);
    }
    world_x_.resize(world);
    world_y_.resize(world);
    world_z_.resize(world);
    arc_voxel_.resize(static_cast<std::size_t>(std::max(max_arc_samples_, geo_[0].table_samples)));
    // Voxel indices are 32-bit in the arc loops (arcVoxels), the words past the map included.
    if (map.size() + arc_voxel_.size() >= static_cast<std::size_t>(std::numeric_limits<int32_t>::max()))
        throw std::invalid_argument("FLS update supports maps of fewer than 2^31 - 1 voxels");
    if (cfg_.fls_once_per_frame || cfg_.fls_free_space) {
        voxel_hit_.assign(map.size() + arc_voxel_.size(), 0);  // + the words outside (arcVoxels)
        touched_.resize(voxel_hit_.size() + 1);
    }
    if (cfg_.fls_free_space)  // half-voxel steps out to the maximum range, with room for rounding
        free_step_samples_.assign(static_cast<std::size_t>(std::max(0.0, 2.0 * model.rangeMax() / map.resolution())) + 4, 0);
    seabed_range_.assign(static_cast<std::size_t>(std::max(model.colCapacity(), model.cols())), 0.0f);
    seabed_row_.assign(seabed_range_.size(), -1);
}

void FlsUpdater::computeSeabedRanges(const Geometry& g, const Eigen::Vector3d& sensor_world, double resolution) {
    const int cols = g.model->cols();
    if (!seabed_) {  // no seabed known: no return is nearer than it
        std::fill(seabed_range_.begin(), seabed_range_.begin() + cols, 0.0f);
        return;
    }
    // A ray s + t d meets the plane z = z0 + g . (xy - c) raised by the margin
    // at t = (depth under s - margin) / (d.z - g . d.xy); over the beam's
    // elevation arc (the longest table: the finest sampling) the nearest such
    // t is where the seabed could first return.
    const SeabedFit& f = *seabed_;
    const double margin = 3.0 * f.rms + 0.5 * resolution;
    const double depth_below = f.depthAt(sensor_world.head<2>()) - sensor_world.z() - margin;
    const int n = g.table_samples;
    for (int col = 0; col < cols; ++col) {
        double nearest = 0.0;  // no steeper ray reaches the seabed: nothing is nearer than it
        bool reaches = false;
        for (int k = 0; k < n; ++k) {
            const std::size_t i = g.table_offset[n] + static_cast<std::size_t>(col) * n + k;
            const Eigen::Vector3f d(world_x_[i], world_y_[i], world_z_[i]);
            const double rise = f.closingRate(d);
            if (rise > 1e-6 && depth_below > 0.0) {
                nearest = reaches ? std::min(nearest, depth_below / rise) : depth_below / rise;
                reaches = true;
            }
        }
        seabed_range_[static_cast<std::size_t>(col)] = static_cast<float>(nearest / resolution);
    }
}

std::size_t FlsUpdater::tableSize(int cols, int nv, int samples) {
    std::size_t total = 0;
    for (int n = nv; n <= samples; ++n) total += static_cast<std::size_t>(cols) * n;
    return total;
}

void FlsUpdater::buildTables(Geometry& g, const FlsModel& model) const {
    g.model = &model;
    g.table_samples = arcSamplesFor(model.rangeMax(), model.elevationMax() - model.elevationMin(),
                                    model.elevationSamples(), arc_spacing_);
    // One direction table per arc length n = N_v .. table_samples, each with
    // n evenly spaced elevations, so every range gets exactly the samples it
    // needs (a subset of one finer table leaves gaps).
    const int nv = model.elevationSamples();
    g.table_offset.assign(static_cast<std::size_t>(g.table_samples) + 1, 0);
    std::size_t total = 0;
    for (int n = nv; n <= g.table_samples; ++n) {
        g.table_offset[n] = total;
        total += static_cast<std::size_t>(model.cols()) * n;
    }
    g.sensor_direction.resize(total);
    const double lo = model.elevationMin(), hi = model.elevationMax();
    for (int n = nv; n <= g.table_samples; ++n)
        for (int c = 0; c < model.cols(); ++c)
            for (int k = 0; k < n; ++k)
                g.sensor_direction[g.table_offset[n] + static_cast<std::size_t>(c) * n + k] =
                    n == nv && !(arc_spacing_ > 0.0) ? model.direction(c, k)  // Eq. 3 exactly
                                                     : model.directionAt(c, n == 1 ? 0.5 * (lo + hi) : lo + k * (hi - lo) / (n - 1));
    g.row_samples.resize(static_cast<std::size_t>(model.rows()));
    for (int r = 0; r < model.rows(); ++r)
        g.row_samples[r] = arcSamplesFor(model.rangeOfRow(r), hi - lo, nv, arc_spacing_);
}

bool FlsUpdater::bind(int geometry, const FlsModel& model) {
    if (geometry < 1 || geometry >= geometries()) return false;
    const int samples = arcSamplesFor(model.rangeMax(), model.elevationMax() - model.elevationMin(),
                                      model.elevationSamples(), arc_spacing_);
    Geometry& g = geo_[static_cast<std::size_t>(geometry)];
    if (samples > max_arc_samples_ || model.rows() > static_cast<int>(g.row_samples.capacity()) ||
        tableSize(model.cols(), model.elevationSamples(), samples) > g.sensor_direction.capacity())
        return false;
    buildTables(g, model);
    return true;
}

int FlsUpdater::arcSamplesFor(double range, double aperture, int nv, double spacing) {
    if (!(spacing > 0.0)) return nv;
    const double arc = std::max(0.0, range) * aperture;
    return std::max(nv, static_cast<int>(std::ceil(arc / spacing)) + 1);
}

int FlsUpdater::arcSamples(double range) const {
    const FlsModel& m = *geo_[current_].model;
    return arcSamplesFor(range, m.elevationMax() - m.elevationMin(), m.elevationSamples(), arc_spacing_);
}

FlsUpdater::Grid FlsUpdater::gridOf(const VoxelMap& map) {
    Grid grid{};
    grid.nx = map.nx();
    grid.ny = map.ny();
    grid.nz = map.nz();
    grid.fnx = static_cast<float>(grid.nx);
    grid.fny = static_cast<float>(grid.ny);
    grid.fnz = static_cast<float>(grid.nz);
    grid.fnx1 = grid.fnx - 1.0f;
    grid.fny1 = grid.fny - 1.0f;
    grid.fnz1 = grid.fnz - 1.0f;
    grid.outside = static_cast<uint32_t>(map.size());
    return grid;
}

FlsUpdateStats FlsUpdater::apply(const FlsFrame& frame, const Eigen::Isometry3d& world_from_sensor, VoxelMap& map) {
    MapWriterSink sink(map);
    return apply(frame, world_from_sensor, map, sink);
}

}  // namespace sonarfusion
