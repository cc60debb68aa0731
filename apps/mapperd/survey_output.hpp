// Survey outputs (issue 13, docs/formats.md): each finalised map's files in
// --map-dir (map_<id>.map, .map.ply, .objects.json) and the first map at
// --map-out, every file written atomically (a temporary renamed over it).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "mapper_node.hpp"

namespace sonarfusion {

struct MapOutputs {
    MapOutputs(std::string out, std::string dir) : map_out(std::move(out)), map_dir(std::move(dir)) {}
    std::string map_out;  // --map-out: the first map (the single-map run's map)
    std::string map_dir;  // --map-dir: every finalised map
    int write_failures = 0;            // a finalised map that could not be written (logged)
    std::vector<std::string> summary;  // one line per published object
};

// Map file + PLY at `path` (+ ".ply"); throws std::runtime_error naming the file.
void writeMapFiles(const VoxelMap& map, const DaemonConfig& cfg, const std::string& path);
// The published objects of a finalised map, with their voxels, as JSON.
void writeObjectsJson(const FinalisedMap& f, const std::string& variant, const std::string& path);
// Publisher::finalised for sf-mapper: writes what `outs` asks for. A failed
// write is logged and counted (outs.write_failures), never thrown: mapping goes on.
void onFinalised(const FinalisedMap& f, const DaemonConfig& cfg, MapOutputs& outs);

}  // namespace sonarfusion
