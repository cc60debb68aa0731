// sf-map-voxels: a saved map's voxels as a table, one line per voxel, with the
// rule that put each object voxel in its object (Segmenter::joinClass) and the
// counts those rules read: log-odds, PS-observed, FLS-touched, PS echoes, PS
// crossings, FLS above-seabed votes. Segmented as sf-eval does (the map's
// variant unless --variant, the mapper config's segmentation, --track-deg for
// the track axis sf-eval takes from the scenario), so its object voxels are
// exactly the set sf-eval scores. tools/bench/voxel_truth.py reads
// it with sf-eval's gt_object.ply and says, per rule, how many of those voxels
// are true (docs/evaluation.md, "Which rule put each voxel in the map").
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "map_file.hpp"
#include "mapper_config_yaml.hpp"
#include "sonarfusion/segmentation.hpp"
#include "sonarfusion/variant.hpp"

using namespace sonarfusion;

int main(int argc, char** argv) {
    CLI::App app{"sf-map-voxels: a saved map's voxels, with the segmentation rule that joined each object voxel"};
    std::string map_path, config_path = std::string(SF_SOURCE_DIR) + "/scenarios/mapper.yaml", variant_name, out_path;
    bool all = false;
    double track_deg = std::numeric_limits<double>::quiet_NaN();
    app.add_option("--map", map_path, "map file written by sf-mapper")->required()->check(CLI::ExistingFile);
    app.add_option("--config", config_path, "the mapper YAML the map is segmented with (as sf-eval --config)")
        ->check(CLI::ExistingFile);
    app.add_option("--variant", variant_name, "segment as this variant (default: the map file's)");
    app.add_option("--track-deg", track_deg,
                   "heading of the survey line, deg from north (the mapper's track axis; sf-eval takes it from the "
                   "scenario's NAV headings): only a map without PS echoes (fls_only) reads it, for its seabed "
                   "estimate along the track; default none, a square window");
    app.add_flag("--all", all, "every voxel some update reached, not only the object voxels");
    app.add_option("--out", out_path, "write the table here (default: standard output)");
    CLI11_PARSE(app, argc, argv);

    std::FILE* out = stdout;
    try {
        const MapFileHeader header = readMapHeader(map_path);
        VoxelMap map{mapConfigOf(header)};
        (void)loadMap(map_path, map);
        MapperConfig cfg = loadDaemonConfig(config_path).mapper;
        const Variant variant = requireVariant(variant_name.empty() ? header.variant : variant_name, "--variant");
        applyVariant(variant, cfg);  // as sf-mapper --variant and sf-eval do
        Segmenter seg(cfg.segmentation, cfg.update.require_ps_observation, map);
        if (std::isfinite(track_deg))
            seg.setAlongTrack(Eigen::Vector2d(std::cos(track_deg * kDegToRad), std::sin(track_deg * kDegToRad)));
        const SegmentationStats& stats = seg.run(map);
        if (!out_path.empty() && !(out = std::fopen(out_path.c_str(), "w"))) {
            std::fprintf(stderr, "sf-map-voxels: cannot write %s\n", out_path.c_str());
            return 2;
        }
        std::fprintf(out, "# sf-map-voxels %s variant %s objects %d resolution %g\n", map_path.c_str(),
                     std::string(variantName(variant)).c_str(), stats.objects, map.resolution());
        std::fprintf(out,
                     "# x y z (voxel centre, NED m) join_class (0 none, 1 PS-confirmed seed or candidate, 2 low "
                     "candidate, 3 FLS-only extension, 4 straight down, 5 off-swath, 6 the seabed's own voxel, "
                     "7 PS-crossed but outweighed, 8 unobserved below) log_odds ps_observed fls_touched ps_echoes "
                     "ps_crossings fls_above_seabed_votes object\n");
        for (std::size_t i = 0; i < map.size(); ++i) {
            const int32_t object = seg.objectLabel(i);
            if (object <= 0 && !(all && (map.logOdds(i) != 0.0f || map.flags(i) != 0))) continue;
            const Eigen::Vector3d c = map.centreOf(map.fromLinear(i));
            std::fprintf(out, "%.4f %.4f %.4f %d %.3f %d %d %d %d %d %d\n", c.x(), c.y(), c.z(), seg.joinClass(i),
                         map.logOdds(i), map.psObserved(i) ? 1 : 0, map.flsTouched(i) ? 1 : 0, map.psEchoCount(i),
                         map.psCrossings(i), map.flsAboveSeabedVotes(i), object);
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "sf-map-voxels: %s\n", e.what());
        if (out != stdout) std::fclose(out);
        return 2;
    }
    if (out != stdout && std::fclose(out) != 0) {
        std::fprintf(stderr, "sf-map-voxels: cannot write %s\n", out_path.c_str());
        return 2;
    }
    return 0;
}
