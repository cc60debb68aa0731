// sf-map2octomap: a map saved by sf-mapper (--map-out, docs/map-format.md) as
// an octomap::OcTree binary (.bt) for octovis; the same conversion as
// sf-mapper --octomap-out (apps/common/octomap_export.hpp).
#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>

#include "map_file.hpp"
#include "octomap_export.hpp"
#include "sonarfusion/config.hpp"

using namespace sonarfusion;

int main(int argc, char** argv) {
    CLI::App app{"sf-map2octomap: sonarfusion map file -> OctoMap OcTree binary (.bt, ENU)"};
    std::string map_path, out_path;
    double p = SegmentationConfig{}.occupied_probability;
    bool quiet = false;
    app.add_option("MAP", map_path, "map file written by sf-mapper --map-out")->required()->check(CLI::ExistingFile);
    app.add_option("OUT", out_path, "OctoMap binary to write (.bt)")->required();
    app.add_option("--occupied-probability", p,
                   "occupied when p exceeds this (the mapper config's segmentation.occupied_probability; default 0.7)");
    app.add_flag("--quiet", quiet, "no summary");
    CLI11_PARSE(app, argc, argv);
    try {
        const MapFileHeader h = readMapHeader(map_path);
        VoxelMap map(mapConfigOf(h));
        loadMap(map_path, map);
        const OctomapExportStats st = writeOctomap(out_path, map, p);
        if (!quiet)
            std::printf("%s: %zu occupied, %zu free voxels at %.3f m (ENU)\n", out_path.c_str(), st.occupied, st.free,
                        h.resolution);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "sf-map2octomap: %s\n", e.what());
        return 1;
    }
    return 0;
}
