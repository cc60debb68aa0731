// sf-fls-evidence: per voxel, in how many FLS frames the mapper voted it (an
// arc of a return above the threshold fell in it) and in how many it freed it
// (it lay before its beam's first return). Together with the evaluator's ground
// truth (tools/bench/fls_likelihood.py) this measures the FLS's inverse
// sensor model: how often a surface is seen through, and how often water is
// voted (docs/algorithm.md, "FLS free-space weight").
//
// With --seabed-depth D it also counts, per voxel, the frames that voted it
// from a return nearer than a flat seabed at depth D anywhere on the beam's
// elevation arc (less --seabed-margin): the ground-truth version of the
// Mapper's own above-seabed count, which judges against the detector's plane
// (docs/algorithm.md, "Off-swath parts"). With --count-looks as well, per voxel,
// the frames in which such a vote was possible at all: the voxel's centre lay
// in the FLS's field of view and nearer than that seabed on its beam, whether
// or not anything returned from its range (the opportunities the above-seabed
// votes are a share of).
//
// The counts come from the very update stream the Mapper applies
// (update_stream.hpp), so they are the mapper's own, frame by frame.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <vector>

#include "sonarfusion/beam_direction.hpp"

#include "update_stream.hpp"

using namespace sonarfusion;

int main(int argc, char** argv) {
    CLI::App app{"sf-fls-evidence: per-voxel FLS vote and free-space frame counts of a mapper run"};
    std::string log_path, config_path = std::string(SF_SOURCE_DIR) + "/scenarios/mapper.yaml", out_path;
    app.add_option("--log", log_path, "LCM log written by sf-sim")->required()->check(CLI::ExistingFile);
    app.add_option("--config", config_path, "mapper YAML config")->check(CLI::ExistingFile);
    app.add_option("--out", out_path, "counts file (format: tools/bench/fls_likelihood.py)")
        ->required();
    double seabed_depth = std::numeric_limits<double>::quiet_NaN(), seabed_margin = 0.1;
    app.add_option("--seabed-depth", seabed_depth,
                   "world z of a flat seabed: also count votes the seabed cannot explain (the voxel "
                   "lies nearer than the seabed does anywhere on its beam's elevation arc)");
    app.add_option("--seabed-margin", seabed_margin, "m subtracted from that nearest seabed range");
    bool count_looks = false;
    app.add_flag("--count-looks", count_looks,
                 "with --seabed-depth: also count, per voxel, the frames that held it in the field of view "
                 "nearer than the seabed on its beam");
    CLI11_PARSE(app, argc, argv);

    DaemonConfig dcfg;
    sfbench::Recording rec;
    try {
        dcfg = loadDaemonConfig(config_path);
        const sfbench::ScenarioLog log = sfbench::loadScenarioLog(log_path, dcfg);
        rec = sfbench::recordUpdateStream(log, dcfg.mapper);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "sf-fls-evidence: %s\n", e.what());
        return 2;
    }
    const sfbench::UpdateStream& s = rec.stream;
    VoxelMap map(dcfg.mapper.map);
    map.initialiseAt(s.map_centre);
    std::vector<uint16_t> voted(map.size(), 0), freed(map.size(), 0), above(map.size(), 0), looks;
    if (count_looks && std::isnan(seabed_depth)) {
        std::fprintf(stderr, "sf-fls-evidence: --count-looks needs --seabed-depth\n");
        return 2;
    }
    const FlsGeometry& fg = dcfg.mapper.fls;
    // The nearest range at which a beam at this bearing meets the flat seabed:
    // over its elevation arc, the steepest ray.
    auto nearestSeabed = [&](const Eigen::Isometry3d& wfs, double bearing) {
        double best = std::numeric_limits<double>::infinity();
        for (int k = 0; k <= 14; ++k) {
            const double e = fg.elevation_min + k * (fg.elevation_max - fg.elevation_min) / 14.0;
            const Eigen::Vector3d d = wfs.linear() * beamDirection(fg.tilt + e, bearing);
            if (d.z() > 1e-6) best = std::min(best, (seabed_depth - wfs.translation().z()) / d.z());
        }
        return best;
    };
    auto bump = [](uint16_t& c) { c = static_cast<uint16_t>(c + (c < std::numeric_limits<uint16_t>::max())); };
    const bool count_above = !std::isnan(seabed_depth);
    if (count_looks) looks.assign(map.size(), 0);
    for (const sfbench::MessageRecord& m : s.messages) {
        if (m.kind != sfbench::MessageRecord::Fls) continue;
        const Eigen::Isometry3d sensor_from_world = m.world_from_sensor.inverse();
        // Per-frame counting: each voxel appears at most once per frame.
        for (uint32_t u = m.begin; u < m.end; ++u) {
            const sfbench::VoxelUpdate& up = s.updates[u];
            if (s.update_flag[u] & VoxelMap::kFlsTouched) {
                bump(voted[up.voxel]);
                if (count_above) {
                    const Eigen::Vector3d ps = sensor_from_world * map.centreOf(map.fromLinear(up.voxel));
                    const double bearing = std::atan2(ps.y(), ps.x());
                    if (ps.norm() < nearestSeabed(m.world_from_sensor, bearing) - seabed_margin) bump(above[up.voxel]);
                }
            }
            else if (up.delta < 0.0f) bump(freed[up.voxel]);
        }
        if (count_looks) {
            // The nearest seabed range per bearing, tabulated across the fan.
            constexpr int kBearings = 193;
            double seabed_at[kBearings];
            const double b0 = -0.5 * fg.fov_horizontal, db = fg.fov_horizontal / (kBearings - 1);
            for (int k = 0; k < kBearings; ++k) seabed_at[k] = nearestSeabed(m.world_from_sensor, b0 + k * db);
            const double half_fov = 0.5 * fg.fov_horizontal;
            const double dep_lo = fg.tilt + fg.elevation_min, dep_hi = fg.tilt + fg.elevation_max;
            for (std::size_t v = 0; v < map.size(); ++v) {
                const Eigen::Vector3d p = sensor_from_world * map.centreOf(map.fromLinear(v));
                if (p.x() <= 0.0) continue;
                const double r = p.norm();
                if (r < fg.range_min || r > fg.range_max) continue;
                const double bearing = std::atan2(p.y(), p.x());
                if (std::abs(bearing) > half_fov) continue;
                const double dep = std::atan2(p.z(), std::hypot(p.x(), p.y()));
                if (dep < dep_lo || dep > dep_hi) continue;
                const int k = static_cast<int>(std::lround((bearing - b0) / db));
                if (r < seabed_at[std::clamp(k, 0, kBearings - 1)] - seabed_margin) bump(looks[v]);
            }
        }
    }
    std::ofstream out(out_path, std::ios::binary);
    const int32_t dims[3] = {map.nx(), map.ny(), map.nz()};
    const double res = map.resolution();
    const double origin[3] = {map.origin().x(), map.origin().y(), map.origin().z()};
    out.write("SFFLSEV1", 8);
    out.write(reinterpret_cast<const char*>(dims), sizeof dims);
    out.write(reinterpret_cast<const char*>(&res), sizeof res);
    out.write(reinterpret_cast<const char*>(origin), sizeof origin);
    out.write(reinterpret_cast<const char*>(voted.data()), static_cast<std::streamsize>(voted.size() * 2));
    out.write(reinterpret_cast<const char*>(freed.data()), static_cast<std::streamsize>(freed.size() * 2));
    if (count_above)
        out.write(reinterpret_cast<const char*>(above.data()), static_cast<std::streamsize>(above.size() * 2));
    if (count_looks)
        out.write(reinterpret_cast<const char*>(looks.data()), static_cast<std::streamsize>(looks.size() * 2));
    if (!out) {
        std::fprintf(stderr, "sf-fls-evidence: cannot write %s\n", out_path.c_str());
        return 1;
    }
    std::printf("%d FLS frames; counts of %zu voxels written to %s\n", s.fls_frames, map.size(), out_path.c_str());
    return 0;
}
