// Where the updaters' voxel updates go. The mapper writes them into its map
// (MapWriterSink); a benchmark or a test can record the very same stream by
// passing its own sink with the same five calls.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>

#include "sonarfusion/voxel_map.hpp"

namespace sonarfusion {

// The sink interface, by example (the updaters take any type with these calls):
//   void add(std::size_t voxel, float delta, uint8_t flag)  // log-odds update, then set flag
//   void echo(std::size_t voxel)                            // a PS echo ended here (flag + count)
//   void ray(origin, carve_end, echo)  // a PS ray starts: carved up to carve_end, its echo at echo
//   void crossed(std::size_t voxel)                         // a PS ray crossed it (counted, carved or spared)
//   void aboveSeabed(std::size_t voxel)                     // an FLS vote the seabed cannot explain
class MapWriterSink {
public:
    explicit MapWriterSink(VoxelMap& map) : map_(map), out_(map.writer()) {}
    void add(std::size_t v, float delta, uint8_t flag) {
        out_.add(v, delta);
        out_.setFlag(v, flag);  // the updaters pass a constant: a plain store of 1, or nothing
    }
    void echo(std::size_t v) {
        map_.setFlag(v, VoxelMap::kPsObserved);
        map_.addPsEcho(v);
    }
    void ray(const Eigen::Vector3d& /*origin*/, const Eigen::Vector3d& /*carve_end*/, const Eigen::Vector3d& /*echo*/) {}
    void aboveSeabed(std::size_t v) { out_.addAboveSeabedVote(v); }
    void crossed(std::size_t v) { out_.addPsCrossing(v); }

private:
    VoxelMap& map_;
    VoxelMap::Writer out_;
};

// DetectorConfig::replay_pings_carve_only: a held PS ping carved into a map
// anchored after it adds only its water. `Inner` gets the carving's free-space
// log-odds updates (every one below zero) without their flag, and the rays;
// the echo, its end-point hit, the crossing counts and the PS-observed flag,
// which count the pings the map was made from, are dropped.
template <class Inner>
class CarvingOnlySink {
public:
    explicit CarvingOnlySink(Inner& inner) : inner_(inner) {}
    void add(std::size_t v, float delta, uint8_t /*flag*/) {
        if (delta < 0.0f) inner_.add(v, delta, 0);
    }
    void echo(std::size_t /*v*/) {}
    void ray(const Eigen::Vector3d& origin, const Eigen::Vector3d& carve_end, const Eigen::Vector3d& echo) {
        inner_.ray(origin, carve_end, echo);
    }
    void crossed(std::size_t /*v*/) {}
    void aboveSeabed(std::size_t /*v*/) {}

private:
    Inner& inner_;
};

}  // namespace sonarfusion
