#include "octomap_export.hpp"

#include <octomap/OcTree.h>

#include <cstdio>
#include <stdexcept>

namespace sonarfusion {

bool octomapOccupied(const VoxelMap& map, std::size_t i, double occupied_probability) {
    const float thr = static_cast<float>(logOddsFromProbability(occupied_probability));
    return map.logOdds(i) > thr;
}

Eigen::Vector3d enuCentreOf(const VoxelMap& map, std::size_t i) {
    const Eigen::Vector3d ned = map.centreOf(map.fromLinear(i));
    return Eigen::Vector3d(ned.y(), ned.x(), -ned.z());
}

OctomapExportStats writeOctomap(const std::string& path, const VoxelMap& map, double occupied_probability) {
    if (!(occupied_probability > 0.0 && occupied_probability < 1.0))
        throw std::runtime_error("OctoMap export: occupied probability must be in (0, 1)");
    octomap::OcTree tree(map.resolution());
    // Leaves are set to the tree's clamping bounds, so the state the binary
    // format keeps (occupied iff log-odds >= the tree's threshold) is ours.
    const float occ = tree.getClampingThresMaxLog(), fre = tree.getClampingThresMinLog();
    OctomapExportStats st;
    for (std::size_t i = 0; i < map.size(); ++i) {
        if (map.logOdds(i) == 0.0f) continue;  // never updated: unknown
        const Eigen::Vector3d c = enuCentreOf(map, i);
        octomap::OcTreeKey key;
        if (!tree.coordToKeyChecked(octomap::point3d(static_cast<float>(c.x()), static_cast<float>(c.y()),
                                                     static_cast<float>(c.z())),
                                    key))
            throw std::runtime_error("OctoMap export: voxel outside OctoMap's key range: " + path);
        const bool o = octomapOccupied(map, i, occupied_probability);
        tree.setNodeValue(key, o ? occ : fre, /*lazy_eval=*/true);
        ++(o ? st.occupied : st.free);
    }
    tree.updateInnerOccupancy();
    const std::string tmp = path + ".tmp";
    if (!tree.writeBinary(tmp)) {
        std::remove(tmp.c_str());
        throw std::runtime_error("cannot write OctoMap " + tmp);
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
        std::remove(tmp.c_str());
        throw std::runtime_error("cannot rename " + tmp + " to " + path);
    }
    return st;
}

}  // namespace sonarfusion
