// The acoustic scene: all meshes in one Embree 3 BVH, each with its acoustic
// impedance. First-hit ray casting gives occlusion (acoustic shadows) for free.
#pragma once

#include <embree3/rtcore.h>

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "embree_device.hpp"
#include "mesh_io.hpp"
#include "scenario.hpp"

namespace sonarfusion::sim {

struct RayHit {
    bool hit = false;
    float range = 0.0f;          // m along the unit direction
    float cos_incidence = 0.0f;  // |cos| of the angle between ray and surface normal
    uint32_t mesh = 0;           // index into the scene's meshes
};

class Scene {
public:
    // Loads every mesh of the spec. Throws std::runtime_error on bad meshes
    // and on any Embree error (which the device also logs to stderr).
    explicit Scene(const SceneSpec& spec);
    // From meshes already in memory (tests); materials[i] belongs to meshes[i].
    // embree_config: Embree's device configuration string ("" = its defaults).
    Scene(const std::vector<TriangleMesh>& meshes, const std::vector<MeshSpec>& materials, double water_impedance,
          const std::string& embree_config = "");
    ~Scene();
    Scene(const Scene&) = delete;
    Scene& operator=(const Scene&) = delete;

    // Casts n rays from one origin (unit directions) and keeps hits in
    // [near, far]. Thread-safe: many threads may cast at once.
    void cast(const Eigen::Vector3f& origin, const Eigen::Vector3f* directions, int n, float near, float far,
              RayHit* hits) const;

    // Pressure reflection coefficient (Z - Z0) / (Z + Z0) of a mesh's material.
    [[nodiscard]] double reflectionCoefficient(uint32_t mesh) const { return reflection_[mesh]; }
    [[nodiscard]] std::size_t triangleCount() const { return triangles_; }
    // Errors Embree reported on this scene's device (none in a good run).
    [[nodiscard]] std::size_t embreeErrorCount() const { return device_->errorCount(); }

private:
    void build(const std::vector<TriangleMesh>& meshes, const std::vector<MeshSpec>& materials, double water_impedance,
               const std::string& embree_config);
    void addMeshes(const std::vector<TriangleMesh>& meshes, const std::vector<MeshSpec>& materials,
                   double water_impedance);

    std::unique_ptr<EmbreeDevice> device_;  // released after scene_ (~Scene)
    RTCScene scene_ = nullptr;
    std::vector<double> reflection_;  // per Embree geometry id (== mesh index)
    std::size_t triangles_ = 0;
};

}  // namespace sonarfusion::sim
