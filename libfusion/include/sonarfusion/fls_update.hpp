// FLS log-odds update (paper Eqs. 5-9): every pixel above the threshold votes
// for the voxels its elevation arc passes through; optionally the beam's
// water before its first return is carved (FLS space carving).
#pragma once

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <vector>

#include "sonarfusion/config.hpp"
#include "sonarfusion/fls_highlight.hpp"
#include "sonarfusion/fls_model.hpp"
#include "sonarfusion/seabed_fit.hpp"
#include "sonarfusion/update_sink.hpp"
#include "sonarfusion/voxel_map.hpp"

namespace sonarfusion {

struct FlsUpdateStats {
    int pixels_above_threshold = 0;
    int points_in_map = 0;
    int points_outside_map = 0;  // skipped, never written
    int voxels_updated = 0;      // occupied updates
    int voxels_freed = 0;        // free-space updates
    int voxels_above_seabed = 0; // voted by a return the seabed cannot explain
};

class FlsUpdater {
public:
    // Scratch for per-frame counting and the arc tables are sized here, once.
    FlsUpdater(const FlsModel& model, const UpdateConfig& cfg, const VoxelMap& map);
    // The same with `geometries` table slots (per-ping geometry, docs/algorithm.md):
    // slot 0 holds `model`'s tables; the others are sized for any geometry of at
    // most model's rows and beams whose longest arc has at most
    // `max_arc_samples` samples (arcSamplesFor), and filled by bind().
    FlsUpdater(const FlsModel& model, const UpdateConfig& cfg, const VoxelMap& map, int geometries,
               int max_arc_samples);

    // Number of arc samples at range r for an aperture (rad): N_v, or with a
    // spacing (m) > 0, max(N_v, ceil(r * aperture / spacing) + 1).
    [[nodiscard]] static int arcSamplesFor(double range, double aperture, int nv, double spacing);
    // The arc spacing in metres this updater uses (0: N_v samples).
    [[nodiscard]] double arcSpacing() const { return arc_spacing_; }
    [[nodiscard]] int geometries() const { return static_cast<int>(geo_.size()); }
    // Recomputes slot `geometry`'s tables for `model` (kept by reference) within
    // the capacity sized at construction: no allocation. False, slot unchanged,
    // when the model does not fit.
    [[nodiscard]] bool bind(int geometry, const FlsModel& model);
    // The slot apply() and the table accessors below use (0 after construction).
    void select(int geometry) { current_ = geometry; }
    [[nodiscard]] int selected() const { return current_; }

    // The seabed the following frames are judged against (none: no vote is
    // counted as above it). A return nearer than this plane, raised by three
    // times its rms scatter plus half a voxel, anywhere on its beam's elevation
    // arc cannot come from the seabed: the voxels it votes are told to the sink
    // (aboveSeabed) to count, once per frame (per candidate point in the paper's
    // counting, without free space) (docs/algorithm.md, "Off-swath parts").
    void setSeabed(const std::optional<SeabedFit>& seabed) { seabed_ = seabed; }
    [[nodiscard]] const std::optional<SeabedFit>& seabed() const { return seabed_; }

    // The level above which a pixel of `frame` stops the free space
    // (firstEchoRow): the image's noise level (noiseLevel) with
    // fls_free_space_noise_sigmas > 0, never above the vote threshold.
    [[nodiscard]] static int freeSpaceStopLevel(const FlsFrame& frame, const UpdateConfig& cfg) {
        return freeSpaceStopLevel(
            cfg.fls_free_space_noise_sigmas > 0.0 ? noiseLevel(frame, cfg.fls_free_space_noise_sigmas) : 255, cfg);
    }
    // The same from the image's noise level already taken (noiseLevel at
    // fls_free_space_noise_sigmas; unused when those are 0).
    [[nodiscard]] static int freeSpaceStopLevel(int image_noise, const UpdateConfig& cfg) {
        return cfg.fls_free_space_noise_sigmas > 0.0 ? std::min(cfg.fls_intensity_threshold, image_noise)
                                                     : cfg.fls_intensity_threshold;
    }

    // The frame must already match the model (FlsModel::frameMatches).
    FlsUpdateStats apply(const FlsFrame& frame, const Eigen::Isometry3d& world_from_sensor, VoxelMap& map);
    // The same updates, in the same order, handed to `sink` (update_sink.hpp)
    // instead of written; `map` gives the grid geometry only.
    template <class Sink>
    FlsUpdateStats apply(const FlsFrame& frame, const Eigen::Isometry3d& world_from_sensor, const VoxelMap& map,
                         Sink& sink) {
        return update<false>(frame, world_from_sensor, map, sink);
    }
    // Only the above-seabed counts apply() would hand `sink` for this frame
    // (aboveSeabed: the same voxels, as often, not always in the same order):
    // no log-odds update, and the
    // pixels the seabed explains and the free space are skipped, so it costs a
    // fraction of apply() (UpdateConfig::fls_seabed_judged_later).
    template <class Sink>
    FlsUpdateStats applyAboveSeabedVotes(const FlsFrame& frame, const Eigen::Isometry3d& world_from_sensor,
                                         const VoxelMap& map, Sink& sink) {
        return update<true>(frame, world_from_sensor, map, sink);
    }

    // Eq. 5 times alpha_F: the increment for a pixel of intensity 255.
    [[nodiscard]] float fullScaleIncrement() const { return increment_; }
    // alpha_F * ln(P_f / (1 - P_f)): the free-space update (< 0).
    [[nodiscard]] float freeIncrement() const { return free_increment_; }
    // Candidate points on the elevation arc at range r: N_v, or with
    // fls_arc_spacing_voxels max(N_v, ceil(r * aperture / spacing) + 1).
    [[nodiscard]] int arcSamples(double range) const;
    // Unit direction (sensor frame) of sample k of column `col` on an arc of n
    // samples (n in [N_v, arcSamples(maximum range)]), lowest elevation first.
    [[nodiscard]] const Eigen::Vector3f& arcDirection(int n, int col, int k) const {
        return geo_[current_].sensor_direction[arcTableOffset(n) + static_cast<std::size_t>(col) * n + k];
    }
    // All the tables in one array, and where the table of n samples starts.
    [[nodiscard]] const std::vector<Eigen::Vector3f>& arcDirections() const { return geo_[current_].sensor_direction; }
    [[nodiscard]] std::size_t arcTableOffset(int n) const { return geo_[current_].table_offset[n]; }

private:
    template <bool kAboveSeabedOnly, class Sink>
    FlsUpdateStats update(const FlsFrame& frame, const Eigen::Isometry3d& world_from_sensor, const VoxelMap& map,
                          Sink& sink);
    // The map's lattice in the arc loops' terms, taken once per frame.
    struct Grid {
        int nx, ny, nz;
        float fnx, fny, fnz;     // bounds on a point's coordinates (voxel units)
        float fnx1, fny1, fnz1;  // the last voxel's coordinates
        uint32_t outside;        // one past the map: sample k outside it gets voxel outside + k
    };
    [[nodiscard]] static Grid gridOf(const VoxelMap& map);
    // Eq. 4 for the n candidate points of one arc: sensor + range * direction
    // (voxel units, map corner at 0) for the directions at `offset` in the
    // selected world tables. Each point's voxel goes to arc_voxel_[0..n), one
    // outside the map (NaN too) to grid.outside + k; returns how many were outside.
    // Branch-free, so the compiler computes several points per instruction.
    int arcVoxels(const Eigen::Vector3f& sensor, float range, std::size_t offset, int n, const Grid& grid);

    // The arc tables of one geometry.
    struct Geometry {
        const FlsModel* model = nullptr;
        int table_samples = 0;                         // samples of the longest arc (at the maximum range)
        std::vector<std::size_t> table_offset;         // per arc length n: start of its table
        std::vector<int> row_samples;                  // arc samples per row
        std::vector<Eigen::Vector3f> sensor_direction; // every table, sensor frame
    };
    void buildTables(Geometry& g, const FlsModel& model) const;
    [[nodiscard]] static std::size_t tableSize(int cols, int nv, int samples);
    // Per column of the selected geometry: the range (voxel units) below which
    // a return cannot be the seabed (seabed_); 0 (none) without a seabed.
    void computeSeabedRanges(const Geometry& g, const Eigen::Vector3d& sensor_world, double resolution);

    UpdateConfig cfg_;
    float increment_;       // delta L_o * alpha_F
    float free_increment_;  // -fls_free_vote_ratio * alpha_F * ln(P_o / (1 - P_o))
    double arc_spacing_ = 0.0;  // m between arc samples; 0: N_v samples
    std::vector<Geometry> geo_;  // slot 0: the constructor's model
    int current_ = 0;
    int max_arc_samples_ = 0;    // capacity of the slots beyond 0
    // The selected tables rotated into the map frame, one array per axis so
    // one arc's points are computed several at a time (arcVoxels).
    std::vector<float> world_x_, world_y_, world_z_;
    std::vector<uint32_t> arc_voxel_;  // one arc's voxels (arcVoxels)
    // The free space's arc samples per half-voxel range step from the
    // nearest row (the same for every beam of a frame); steps past its
    // capacity (a geometry bound later reaching further) are computed.
    std::vector<int> free_step_samples_;
    // Per voxel, this frame: the strongest intensity that voted it,
    // kHitAboveSeabed when a vote the seabed cannot explain hit it, kTouched
    // once a vote or the free space reached it (kTouched alone: freed); 0 =
    // untouched. One load and one store per candidate point, with no index to
    // follow (it was a per-voxel slot into a per-frame array: two dependent
    // loads, 4 MB more). One word more per arc sample past the map: where
    // points outside it land (Grid::outside), so the loops need no branch.
    static constexpr uint16_t kHitAboveSeabed = 0x100;
    static constexpr uint16_t kTouched = 0x200;
    std::vector<uint16_t> voxel_hit_;
    // Voxels hit or freed in this frame, in first-touch order; one longer than
    // voxel_hit_: the slot each loop writes before it counts.
    std::vector<uint32_t> touched_;
    std::optional<SeabedFit> seabed_;
    std::vector<float> seabed_range_;               // per column, voxel units (computeSeabedRanges)
    std::vector<int> seabed_row_;                   // per column: the row of seabed_range_ (FlsHighlight)
    FlsHighlight highlight_;                        // per frame, with fls_highlight_above_seabed and a seabed
};

inline int FlsUpdater::arcVoxels(const Eigen::Vector3f& sensor, float range, std::size_t offset, int n,
                                  const Grid& grid) {
    const float* dx = world_x_.data() + offset;
    const float* dy = world_y_.data() + offset;
    const float* dz = world_z_.data() + offset;
    uint32_t* arc = arc_voxel_.data();
    int outside = 0;
    for (int k = 0; k < n; ++k) {  // Eq. 4, in voxel units
        const float px = sensor.x() + range * dx[k], py = sensor.y() + range * dy[k], pz = sensor.z() + range * dz[k];
        // Bounds on the raw coordinates (NaN fails them), joined with & not &&: no branch.
        const bool inside = (px >= 0.0f) & (py >= 0.0f) & (pz >= 0.0f) & (px < grid.fnx) & (py < grid.fny) &
                            (pz < grid.fnz);
        // Clamped into the grid first, so the conversion is defined for any value;
        // inside it they are >= 0, where truncation equals floor().
        const int32_t ix = static_cast<int32_t>(std::min(std::max(0.0f, px), grid.fnx1));
        const int32_t iy = static_cast<int32_t>(std::min(std::max(0.0f, py), grid.fny1));
        const int32_t iz = static_cast<int32_t>(std::min(std::max(0.0f, pz), grid.fnz1));
        // latticeIndex in 32-bit arithmetic (its size_t would keep SSE2 from
        // vectorising the loop). Outside: a word of its own per sample, so
        // consecutive outside points do not wait on each other's store to one word.
        arc[k] = inside ? static_cast<uint32_t>((iz * grid.ny + iy) * grid.nx + ix) : grid.outside + static_cast<uint32_t>(k);
        outside += !inside;
    }
    return outside;
}

// Template body: the mapper instantiates it with MapWriterSink, the bench with a recorder.
template <bool kAboveSeabedOnly, class Sink>
FlsUpdateStats FlsUpdater::update(const FlsFrame& frame, const Eigen::Isometry3d& world_from_sensor, const VoxelMap& map,
                                  Sink& sink) {
    FlsUpdateStats st;
    const Geometry& g = geo_[current_];
    const FlsModel& model = *g.model;
    const Eigen::Matrix3f rot = world_from_sensor.linear().cast<float>();
    for (std::size_t i = 0; i < g.sensor_direction.size(); ++i) {
        const Eigen::Vector3f d = rot * g.sensor_direction[i];
        world_x_[i] = d.x();
        world_y_[i] = d.y();
        world_z_[i] = d.z();
    }
    // Work relative to the map's min corner in voxel units: small numbers, float is exact enough.
    const float inv_res = static_cast<float>(1.0 / map.resolution());
    const Eigen::Vector3f sensor = ((world_from_sensor.translation() - map.origin()) / map.resolution()).cast<float>();
    const Grid grid = gridOf(map);
    const bool dedupe = cfg_.fls_once_per_frame || cfg_.fls_free_space;
    std::size_t n_touched = 0;
    computeSeabedRanges(g, world_from_sensor.translation(), map.resolution());
    const bool highlights = cfg_.fls_highlight_above_seabed && seabed_.has_value();
    // The image's noise level, taken once: the free space stops above it, and
    // the highlights rank only pixels above it (water and shadow returned
    // nothing); 4 robust sigmas for the highlights when the free space's are 0.
    const double noise_sigmas = cfg_.fls_free_space_noise_sigmas > 0.0 ? cfg_.fls_free_space_noise_sigmas : 4.0;
    const bool needs_noise = highlights || (cfg_.fls_free_space && cfg_.fls_free_space_noise_sigmas > 0.0);
    const int image_noise = needs_noise ? noiseLevel(frame, noise_sigmas) : 255;
    if (highlights) {
        // Per beam, the row where the seabed could first return (rows run from the far end).
        for (int col = 0; col < frame.cols; ++col) {
            const float nearest = seabed_range_[static_cast<std::size_t>(col)] * static_cast<float>(map.resolution());
            seabed_row_[static_cast<std::size_t>(col)] = nearest > 0.0f ? model.lastRowAtLeast(nearest) : -1;
        }
        highlight_.compute(frame, cfg_.fls_intensity_threshold, image_noise, seabed_row_.data());
    }

    for (int row = 0; row < frame.rows; ++row) {
        const uint8_t* line = frame.data + static_cast<std::size_t>(row) * frame.cols;
        const float range = static_cast<float>(model.rangeOfRow(row)) * inv_res;
        const int n = g.row_samples[row];
        const std::size_t row_table = g.table_offset[n];
        for (int col = 0; col < frame.cols; ++col) {
            const uint8_t intensity = line[col];
            if (intensity <= cfg_.fls_intensity_threshold) continue;  // paper 2.2: > 150 only
            ++st.pixels_above_threshold;
            const bool above_seabed =
                range < seabed_range_[static_cast<std::size_t>(col)] || (highlights && highlight_.at(row, col));
            if (kAboveSeabedOnly && !above_seabed) continue;
            const uint16_t above_flag = above_seabed ? kHitAboveSeabed : 0;
            const int outside = arcVoxels(sensor, range, row_table + static_cast<std::size_t>(col) * n, n, grid);
            st.points_outside_map += outside;
            st.points_in_map += n - outside;
            const uint32_t* arc = arc_voxel_.data();
            if (!cfg_.fls_once_per_frame) {
                for (int k = 0; k < n; ++k) {
                    const uint32_t v = arc[k];
                    if (v >= grid.outside) continue;  // skipped, never written
                    // Eq. 6 per candidate point, then the clamp of Eq. 8.
                    if constexpr (!kAboveSeabedOnly) {
                        sink.add(v, increment_ * intensity / 255.0f, VoxelMap::kFlsTouched);
                        ++st.voxels_updated;
                    }
                    if (!dedupe && above_seabed) {
                        sink.aboveSeabed(v);
                        ++st.voxels_above_seabed;
                    }
                }
                if (!dedupe) continue;
            }  // and with dedupe remember the hits, so free space skips them
            for (int k = 0; k < n; ++k) {
                const uint32_t v = arc[k];
                uint16_t& h = voxel_hit_[v];
                // Appended unconditionally, kept only on first touch: no branch
                // to mispredict where neighbouring rows meet the same voxel.
                touched_[n_touched] = v;
                n_touched += h == 0;
                h = static_cast<uint16_t>(std::max<uint16_t>(h & 0xff, intensity) | (h & kHitAboveSeabed) | above_flag |
                                          kTouched);
            }
        }
    }
    if (cfg_.fls_free_space && !kAboveSeabedOnly) {
        // Per beam, the water before its first return: arcs stepped half a voxel
        // apart in range, up to a voxel diagonal short of that return (so no
        // voxel holding a point of the returning arc is carved). Voxels this
        // frame also hit keep only the hit.
        const float margin = std::sqrt(3.0f);
        const float r_min = static_cast<float>(model.rangeOfRow(frame.rows - 1)) * inv_res;
        const int noise = freeSpaceStopLevel(image_noise, cfg_);
        int steps_known = 0;  // free_step_samples_[0..steps_known) hold this frame's
        for (int col = 0; col < frame.cols; ++col) {
            const int first = firstEchoRow(frame, col, cfg_.fls_intensity_threshold, noise);
            const float r_first =  // no return: all water
                static_cast<float>(first < 0 ? model.rangeMax() : model.rangeOfRow(first)) * inv_res;
            int step = 0;
            for (float r = r_min; r < r_first - margin; r += 0.5f, ++step) {
                // Every beam steps through the same ranges: their arc lengths
                // are taken once per frame (as far as the table holds them).
                int n;
                if (step < steps_known) {
                    n = free_step_samples_[static_cast<std::size_t>(step)];
                } else {
                    n = arcSamples(r * map.resolution());
                    if (step == steps_known && step < static_cast<int>(free_step_samples_.size()))
                        free_step_samples_[static_cast<std::size_t>(steps_known++)] = n;
                }
                (void)arcVoxels(sensor, r, g.table_offset[n] + static_cast<std::size_t>(col) * n, n, grid);
                for (int k = 0; k < n; ++k) {
                    const uint32_t v = arc_voxel_[static_cast<std::size_t>(k)];
                    uint16_t& h = voxel_hit_[v];
                    touched_[n_touched] = v;  // kept only on first touch, as above
                    n_touched += h == 0;
                    h |= kTouched;  // a hit word already holds it
                }
            }
        }
    }
    // Per-frame counting: each voxel gets Eq. 6 once, with its strongest
    // intensity, or the free-space update once.
    for (std::size_t i = 0; i < n_touched; ++i) {
        const uint32_t v = touched_[i];
        const uint16_t h = voxel_hit_[v];
        if (v >= grid.outside) {  // the points outside the map: counted above, never written
            voxel_hit_[v] = 0;
            continue;
        }
        if (h == kTouched) {  // freed, no vote (never with kAboveSeabedOnly: no free space)
            if constexpr (!kAboveSeabedOnly) sink.add(v, free_increment_, 0);
            ++st.voxels_freed;
        } else {
            if constexpr (!kAboveSeabedOnly) {
                if (cfg_.fls_once_per_frame) {
                    sink.add(v, increment_ * static_cast<float>(h & 0xff) / 255.0f, VoxelMap::kFlsTouched);
                    ++st.voxels_updated;
                }  // else: every hit point was applied in the loop above
            }
            if (h & kHitAboveSeabed) {
                sink.aboveSeabed(v);
                ++st.voxels_above_seabed;
            }
        }
        voxel_hit_[v] = 0;
    }
    return st;
}

}  // namespace sonarfusion
