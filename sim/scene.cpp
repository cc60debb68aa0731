#include "scene.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace sonarfusion::sim {

Scene::Scene(const SceneSpec& spec) {
    std::vector<TriangleMesh> meshes;
    meshes.reserve(spec.meshes.size());
    for (const MeshSpec& m : spec.meshes) meshes.push_back(loadMesh(MeshSource{m.path, {m.scale, m.pose()}}));
    build(meshes, spec.meshes, spec.water_impedance, "");
}

Scene::Scene(const std::vector<TriangleMesh>& meshes, const std::vector<MeshSpec>& materials, double water_impedance,
             const std::string& embree_config) {
    if (meshes.size() != materials.size()) throw std::invalid_argument("Scene: one material per mesh");
    build(meshes, materials, water_impedance, embree_config);
}

void Scene::build(const std::vector<TriangleMesh>& meshes, const std::vector<MeshSpec>& materials,
                  double water_impedance, const std::string& embree_config) {
    device_ = std::make_unique<EmbreeDevice>(embree_config);  // logs and records every Embree error
    scene_ = rtcNewScene(device_->get());
    if (!scene_) {
        device_->check("rtcNewScene");
        throw std::runtime_error("Embree: rtcNewScene failed");
    }
    try {
        addMeshes(meshes, materials, water_impedance);
    } catch (...) {  // ~Scene does not run when a constructor throws
        rtcReleaseScene(scene_);
        scene_ = nullptr;
        throw;
    }
}

void Scene::addMeshes(const std::vector<TriangleMesh>& meshes, const std::vector<MeshSpec>& materials,
                      double water_impedance) {
    rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);  // built once, cast millions of times
    for (std::size_t i = 0; i < meshes.size(); ++i) {
        const TriangleMesh& m = meshes[i];
        RTCGeometry geom = rtcNewGeometry(device_->get(), RTC_GEOMETRY_TYPE_TRIANGLE);
        if (!geom) {
            device_->check("rtcNewGeometry (mesh " + std::to_string(i) + ")");
            throw std::runtime_error("Embree: rtcNewGeometry failed (mesh " + std::to_string(i) + ")");
        }
        float* v = nullptr;
        unsigned* idx = nullptr;
        try {
            v = static_cast<float*>(device_->newGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, RTC_FORMAT_FLOAT3,
                                                               3 * sizeof(float), m.vertices.size(),
                                                               "vertex buffer of mesh " + std::to_string(i)));
            idx = static_cast<unsigned*>(device_->newGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, RTC_FORMAT_UINT3,
                                                                    3 * sizeof(unsigned), m.triangles.size(),
                                                                    "index buffer of mesh " + std::to_string(i)));
        } catch (...) {
            rtcReleaseGeometry(geom);
            throw;
        }
        for (std::size_t k = 0; k < m.vertices.size(); ++k)
            for (int a = 0; a < 3; ++a) v[3 * k + a] = static_cast<float>(m.vertices[k][a]);
        for (std::size_t k = 0; k < m.triangles.size(); ++k)
            for (int a = 0; a < 3; ++a) idx[3 * k + a] = m.triangles[k][a];
        rtcCommitGeometry(geom);
        const unsigned id = rtcAttachGeometry(scene_, geom);
        rtcReleaseGeometry(geom);
        if (id != i) throw std::runtime_error("Embree: unexpected geometry id");
        const double z = materials[i].impedance;
        reflection_.push_back((z - water_impedance) / (z + water_impedance));
        triangles_ += m.triangles.size();
    }
    rtcCommitScene(scene_);
    device_->check("scene build");
}

Scene::~Scene() {
    if (scene_) rtcReleaseScene(scene_);
}

void Scene::cast(const Eigen::Vector3f& origin, const Eigen::Vector3f* directions, int n, float near, float far,
                 RayHit* hits) const {
    constexpr int kChunk = 256;  // stream size for rtcIntersect1M
    RTCRayHit rays[kChunk];
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;  // rays of one beam are nearly parallel
    for (int start = 0; start < n; start += kChunk) {
        const int count = std::min(kChunk, n - start);
        for (int i = 0; i < count; ++i) {
            RTCRayHit& r = rays[i];
            const Eigen::Vector3f& d = directions[start + i];
            r.ray.org_x = origin.x();
            r.ray.org_y = origin.y();
            r.ray.org_z = origin.z();
            r.ray.dir_x = d.x();
            r.ray.dir_y = d.y();
            r.ray.dir_z = d.z();
            r.ray.tnear = near;
            r.ray.tfar = far;  // returns past max range are never reported
            r.ray.time = 0.0f;
            r.ray.mask = 0xFFFFFFFFu;
            r.ray.id = static_cast<unsigned>(i);
            r.ray.flags = 0;
            r.hit.geomID = RTC_INVALID_GEOMETRY_ID;
            r.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        }
        rtcIntersect1M(scene_, &context, rays, static_cast<unsigned>(count), sizeof(RTCRayHit));
        for (int i = 0; i < count; ++i) {
            const RTCRayHit& r = rays[i];
            RayHit& h = hits[start + i];
            h.hit = r.hit.geomID != RTC_INVALID_GEOMETRY_ID;
            if (!h.hit) continue;
            const Eigen::Vector3f normal(r.hit.Ng_x, r.hit.Ng_y, r.hit.Ng_z);
            const float norm = normal.norm();
            h.range = r.ray.tfar;
            h.cos_incidence = norm > 0.0f ? std::fabs(normal.dot(directions[start + i])) / norm : 0.0f;
            h.mesh = r.hit.geomID;
        }
    }
}

}  // namespace sonarfusion::sim
