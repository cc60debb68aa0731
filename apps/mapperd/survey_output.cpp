#include "survey_output.hpp"

#include <spdlog/spdlog.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>

#include "map_file.hpp"

namespace sonarfusion {

void writeMapFiles(const VoxelMap& map, const DaemonConfig& cfg, const std::string& path) {
    try {
        saveMap(path, map, cfg.variant);
        savePly(path + ".ply", map, cfg.mapper.segmentation.occupied_probability);
    } catch (...) {
        // A full disk: no half-written temporary is left; the last good map stays.
        std::remove((path + ".tmp").c_str());
        std::remove((path + ".ply.tmp").c_str());
        throw;
    }
    spdlog::info("map written to {} (+ .ply)", path);
}

void writeObjectsJson(const FinalisedMap& f, const std::string& variant, const std::string& path) {
    const std::string tmp = path + ".tmp";
    FILE* out = std::fopen(tmp.c_str(), "w");
    if (!out) throw std::runtime_error("cannot write " + tmp + ": " + std::strerror(errno));
    const VoxelMap& m = f.map;
    std::fprintf(out, "{\"map_id\": %d, \"variant\": \"%s\", \"origin\": [%.6f, %.6f, %.6f], \"resolution\": %.6f, "
                      "\"dims\": [%d, %d, %d],\n \"objects\": [",
                 f.map_id, variant.c_str(), m.origin().x(), m.origin().y(), m.origin().z(), m.resolution(), m.nx(),
                 m.ny(), m.nz());
    for (std::size_t k = 0; k < f.objects.size(); ++k) {
        const ObjectInfo& o = f.objects[k];
        std::fprintf(out,
                     "%s\n  {\"id\": %d, \"voxel_count\": %d, \"volume_m3\": %.6f, \"centroid\": [%.4f, %.4f, %.4f], "
                     "\"bbox_min\": [%.4f, %.4f, %.4f], \"bbox_max\": [%.4f, %.4f, %.4f], \"height_m\": %.4f, "
                     "\"ps_confirmed\": %s, \"voxels\": [",
                     k ? "," : "", o.id, o.voxel_count, o.volume_m3, o.centroid.x(), o.centroid.y(), o.centroid.z(),
                     o.bbox_min.x(), o.bbox_min.y(), o.bbox_min.z(), o.bbox_max.x(), o.bbox_max.y(), o.bbox_max.z(),
                     o.height_m, o.ps_confirmed ? "true" : "false");
        bool first = true;
        for (std::size_t i = 0; i < m.size(); ++i)
            if (f.segmenter.objectLabel(i) == o.id) {
                std::fprintf(out, first ? "%zu" : ", %zu", i);
                first = false;
            }
        std::fprintf(out, "]}");
    }
    std::fprintf(out, "\n]}\n");
    const bool ok = std::fflush(out) == 0 && fsync(fileno(out)) == 0;
    if (std::fclose(out) != 0 || !ok || std::rename(tmp.c_str(), path.c_str()) != 0) {
        std::remove(tmp.c_str());
        throw std::runtime_error("cannot write " + path);
    }
}

void onFinalised(const FinalisedMap& f, const DaemonConfig& cfg, MapOutputs& outs) {
    // A reopened map (survey.reopen_on_revisit) is finalised again: its objects replace the earlier ones.
    const std::string prefix = fmt::format("map {} object ", f.map_id);
    outs.summary.erase(std::remove_if(outs.summary.begin(), outs.summary.end(),
                                      [&](const std::string& s) { return s.rfind(prefix, 0) == 0; }),
                       outs.summary.end());
    for (const ObjectInfo& o : f.objects)
        outs.summary.push_back(fmt::format("map {} object {}: {} voxels, {:.3f} m3, centroid {:.2f} {:.2f} {:.2f}, "
                                           "height {:.2f} m{}",
                                           f.map_id, o.id, o.voxel_count, o.volume_m3, o.centroid.x(), o.centroid.y(),
                                           o.centroid.z(), o.height_m, o.ps_confirmed ? "" : " (not PS-confirmed)"));
    // Mid-mission, a failed write (a full disk) must not stop the mapping of
    // the next object: it is logged and counted, and the run exits 1 at the end.
    try {
        if (!outs.map_dir.empty()) {
            const std::string base = outs.map_dir + "/map_" + std::to_string(f.map_id);
            writeMapFiles(f.map, cfg, base + ".map");
            writeObjectsJson(f, cfg.variant, base + ".objects.json");
        }
        if (f.map_id == 1 && !outs.map_out.empty()) writeMapFiles(f.map, cfg, outs.map_out);
    } catch (const std::exception& e) {
        spdlog::error("map {}: {}", f.map_id, e.what());
        ++outs.write_failures;
    }
}

}  // namespace sonarfusion
