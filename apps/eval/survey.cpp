// Survey scoring: see survey.hpp (no CGAL in this file).
#include "survey.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <stdexcept>

#include "distance_transform.hpp"
#include "figures.hpp"
#include "ground_truth.hpp"
#include "map_file.hpp"
#include "sonarfusion/segmentation.hpp"
#include "sonarfusion/variant.hpp"
#include "sonarfusion/voxel_map.hpp"
#include "voxelise.hpp"

namespace sonarfusion::eval {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

bool boxesOverlap(const Eigen::Vector3d& alo, const Eigen::Vector3d& ahi, const Eigen::Vector3d& blo,
                  const Eigen::Vector3d& bhi) {
    return (alo.array() <= bhi.array()).all() && (blo.array() <= ahi.array()).all();
}

double distanceToBox(const Eigen::Vector3d& p, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
    return (p.cwiseMax(lo).cwiseMin(hi) - p).norm();
}

Eigen::Vector3d gridMax(const GridSpec& g) {
    return g.origin + Eigen::Vector3d(g.nx, g.ny, g.nz) * g.resolution;
}

// Triangles of `mesh` whose bounds meet [lo, hi] (the vertex list is kept whole).
TriangleMesh cropped(const TriangleMesh& mesh, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
    TriangleMesh out;
    out.vertices = mesh.vertices;
    for (const auto& t : mesh.triangles) {
        const Eigen::Vector3d &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
        if (boxesOverlap(a.cwiseMin(b).cwiseMin(c), a.cwiseMax(b).cwiseMax(c), lo, hi)) out.triangles.push_back(t);
    }
    return out;
}

Eigen::Vector3d vec3(const json& j, const std::string& what, const std::string& path) {
    if (!j.is_array() || j.size() != 3) throw std::runtime_error(path + ": '" + what + "' is not [x, y, z]");
    return {j[0].get<double>(), j[1].get<double>(), j[2].get<double>()};
}

json vecJson(const Eigen::Vector3d& v) { return json::array({v.x(), v.y(), v.z()}); }
json optional(const std::optional<double>& v) { return v ? json(*v) : json(nullptr); }

const char* roleName(MatchRole r) {
    switch (r) {
        case MatchRole::Match: return "match";
        case MatchRole::Duplicate: return "duplicate";
        case MatchRole::False: return "false";
    }
    return "false";
}

std::string cell(const std::optional<double>& v, int precision) {
    if (!v) return "-";
    std::ostringstream o;
    o << std::fixed << std::setprecision(precision) << *v;
    return o.str();
}

}  // namespace

// ---------------------------------------------------------------- truth

SurveyTruth makeSurveyTruth(const std::vector<mesh::MeshSource>& object_meshes, const std::vector<mesh::MeshSource>& seabed_meshes,
                            const std::vector<SensorRun>& runs, const VisibilityOptions& options) {
    std::vector<SurveyTrueObject> objects;
    for (const auto& p : object_meshes) {
        SurveyTrueObject o;
        o.name = fs::path(p.path).stem().string();
        o.mesh = loadMesh(p);
        objects.push_back(std::move(o));
    }
    std::vector<TriangleMesh> seabed;
    for (const auto& p : seabed_meshes) seabed.push_back(loadMesh(p));
    return makeSurveyTruth(std::move(objects), seabed, runs, options);
}

SurveyTruth makeSurveyTruth(std::vector<SurveyTrueObject> objects, const std::vector<TriangleMesh>& seabed,
                            const std::vector<SensorRun>& runs, const VisibilityOptions& options) {
    SurveyTruth truth;
    for (const auto& r : runs) truth.run_names.push_back(r.name);
    for (auto& o : objects) meshBounds(o.mesh, o.lo, o.hi);
    double reach = 0.0;
    for (const auto& r : runs) reach = std::max(reach, r.fov.range_max);
    for (auto& o : objects) {
        // A pose farther than its range from every point of the object sees none of it; a sight
        // line to the object stays within `reach` of it, so only occluders there can block it.
        const Eigen::Vector3d lo = o.lo.array() - reach - 1e-6, hi = o.hi.array() + reach + 1e-6;
        std::vector<TriangleMesh> occluders;
        for (const auto& other : objects)
            if (boxesOverlap(other.lo, other.hi, lo, hi)) occluders.push_back(other.mesh);
        for (const auto& s : seabed) occluders.push_back(cropped(s, lo, hi));
        std::vector<SensorRun> near;
        for (const auto& r : runs) {
            SensorRun n{r.name, r.fov, {}};
            for (const auto& pose : r.poses)
                if (distanceToBox(pose.position, o.lo, o.hi) <= r.fov.range_max + 1e-6) n.poses.push_back(pose);
            near.push_back(std::move(n));
        }
        o.samples = sampleVisibleSurface({o.mesh}, occluders, near, options);
    }
    truth.objects = std::move(objects);
    return truth;
}

void truthInMaps(const SurveyTruth& truth, std::vector<SurveyMap>& maps) {
    for (SurveyMap& m : maps) {
        m.truths.clear();
        const Eigen::Vector3d glo = m.grid.origin, ghi = gridMax(m.grid);
        for (std::size_t t = 0; t < truth.objects.size(); ++t) {
            const SurveyTrueObject& o = truth.objects[t];
            if (!boxesOverlap(o.lo, o.hi, glo, ghi)) continue;
            const MeshVoxels v = voxeliseMesh(o.mesh, m.grid);
            if (countSet(v.solid) == 0) continue;
            TrueInGrid g;
            g.true_index = static_cast<int>(t);
            g.solid = v.solid;
            g.visible = markVisibleVoxels(m.grid, v.surface, o.samples, ~0u);
            for (std::size_t k = 0; k < truth.run_names.size() && k < 32; ++k)
                g.visible_by_run.push_back(markVisibleVoxels(m.grid, v.surface, o.samples, 1u << k));
            g.clipped = !((o.lo.array() >= glo.array()).all() && (o.hi.array() <= ghi.array()).all());
            m.truths.push_back(std::move(g));
        }
    }
}

// ---------------------------------------------------------------- input

void readObjectsJson(const std::string& path, SurveyMap& map) {
    std::ifstream in(path);
    if (!in) throw std::runtime_error(path + ": cannot open");
    json j;
    try {
        j = json::parse(in);
    } catch (const json::exception& e) {
        throw std::runtime_error(path + ": not JSON: " + e.what());
    }
    try {
        if (j.contains("map_id") && j["map_id"].get<int>() != map.map_id)
            throw std::runtime_error(path + ": map_id " + std::to_string(j["map_id"].get<int>()) + " is not the file's " +
                                     std::to_string(map.map_id));
        const GridSpec& g = map.grid;
        if (j.contains("origin") && (vec3(j["origin"], "origin", path) - g.origin).cwiseAbs().maxCoeff() > 1e-6)
            throw std::runtime_error(path + ": origin differs from the map file's");
        if (j.contains("resolution") && std::abs(j["resolution"].get<double>() - g.resolution) > 1e-9)
            throw std::runtime_error(path + ": resolution differs from the map file's");
        if (j.contains("dims")) {
            const json& d = j["dims"];
            if (!d.is_array() || d.size() != 3 || d[0].get<int>() != g.nx || d[1].get<int>() != g.ny ||
                d[2].get<int>() != g.nz)
                throw std::runtime_error(path + ": dims differ from the map file's");
        }
        if (j.contains("variant") && j["variant"].is_string() && !map.variant.empty() &&
            j["variant"].get<std::string>() != map.variant)
            throw std::runtime_error(path + ": variant differs from the map file's");
        if (!j.contains("objects") || !j["objects"].is_array()) throw std::runtime_error(path + ": no 'objects' list");
        map.objects.clear();
        for (const json& o : j["objects"]) {
            PredictedObject p;
            p.id = o.at("id").get<int>();
            if (!o.contains("voxels") || !o["voxels"].is_array())
                throw std::runtime_error(path + ": object " + std::to_string(p.id) + " has no 'voxels' list");
            for (const json& v : o["voxels"]) {
                const auto i = v.get<long long>();
                if (i < 0 || static_cast<std::size_t>(i) >= g.size())
                    throw std::runtime_error(path + ": object " + std::to_string(p.id) + ": voxel index " +
                                             std::to_string(i) + " outside the map's grid");
                p.voxels.push_back(static_cast<std::size_t>(i));
            }
            std::sort(p.voxels.begin(), p.voxels.end());
            p.voxels.erase(std::unique(p.voxels.begin(), p.voxels.end()), p.voxels.end());
            p.voxel_count = o.value("voxel_count", static_cast<int>(p.voxels.size()));
            p.volume_m3 = o.value("volume_m3", 0.0);
            p.height_m = o.value("height_m", 0.0);
            p.ps_confirmed = o.value("ps_confirmed", false);
            if (o.contains("centroid")) p.centroid = vec3(o["centroid"], "centroid", path);
            if (o.contains("bbox_min")) p.bbox_min = vec3(o["bbox_min"], "bbox_min", path);
            if (o.contains("bbox_max")) p.bbox_max = vec3(o["bbox_max"], "bbox_max", path);
            for (const auto& q : map.objects)
                if (q.id == p.id) throw std::runtime_error(path + ": object id " + std::to_string(p.id) + " twice");
            map.objects.push_back(std::move(p));
        }
    } catch (const json::exception& e) {
        throw std::runtime_error(path + ": " + e.what());
    }
    map.objects_path = path;
    map.objects_source = "published";
}

std::vector<SurveyMap> readSurveyDir(const std::string& dir) {
    if (!fs::is_directory(dir)) throw std::runtime_error(dir + ": not a folder");
    const std::regex name("map_([0-9]+)\\.map");
    std::vector<SurveyMap> maps;
    for (const auto& e : fs::directory_iterator(dir)) {
        std::smatch m;
        const std::string file = e.path().filename().string();
        if (!e.is_regular_file() || !std::regex_match(file, m, name)) continue;
        SurveyMap s;
        s.map_id = std::stoi(m[1].str());
        s.map_path = e.path().string();
        const MapFileHeader h = readMapHeader(s.map_path);
        s.variant = h.variant;
        s.grid = GridSpec{Eigen::Vector3d(h.origin[0], h.origin[1], h.origin[2]), h.resolution, h.nx, h.ny, h.nz};
        maps.push_back(std::move(s));
    }
    std::sort(maps.begin(), maps.end(), [](const SurveyMap& a, const SurveyMap& b) { return a.map_id < b.map_id; });
    for (std::size_t k = 1; k < maps.size(); ++k)
        if (maps[k].map_id == maps[k - 1].map_id)
            throw std::runtime_error(dir + ": two files for map " + std::to_string(maps[k].map_id));
    for (SurveyMap& s : maps) {
        const std::string objects = (fs::path(dir) / ("map_" + std::to_string(s.map_id) + ".objects.json")).string();
        if (fs::exists(objects)) readObjectsJson(objects, s);
        else s.objects_source = "segmented";
    }
    return maps;
}

void segmentSurveyMap(SurveyMap& map, const MapperConfig& base, const Eigen::Vector2d& along_track) {
    const MapFileHeader h = readMapHeader(map.map_path);
    VoxelMap vm(mapConfigOf(h));
    loadMap(map.map_path, vm);
    const auto variant = parseVariant(h.variant);
    if (!variant) throw std::runtime_error(map.map_path + ": unknown variant '" + h.variant + "'");
    MapperConfig cfg = base;
    applyVariant(*variant, cfg);  // as sf-mapper --variant does
    Segmenter seg(cfg.segmentation, cfg.update.require_ps_observation, vm);
    seg.setAlongTrack(along_track);
    seg.run(vm);
    map.objects.clear();
    std::map<int, std::size_t> slot;
    for (const ObjectInfo& info : seg.objects()) {
        PredictedObject p;
        p.id = info.id;
        p.voxel_count = info.voxel_count;
        p.volume_m3 = info.volume_m3;
        p.height_m = info.height_m;
        p.centroid = info.centroid;
        p.bbox_min = info.bbox_min;
        p.bbox_max = info.bbox_max;
        p.ps_confirmed = cfg.update.require_ps_observation;  // the variants that require PS confirmation
        slot[info.id] = map.objects.size();
        map.objects.push_back(std::move(p));
    }
    for (std::size_t i = 0; i < vm.size(); ++i) {
        const int label = seg.objectLabel(i);
        if (label <= 0) continue;
        const auto it = slot.find(label);
        if (it != slot.end()) map.objects[it->second].voxels.push_back(i);
    }
    map.objects_source = "segmented";
}

// ---------------------------------------------------------------- matching

std::vector<Assignment> matchSurvey(const std::vector<SurveyMap>& maps, int true_objects) {
    std::vector<Assignment> out;
    for (std::size_t mi = 0; mi < maps.size(); ++mi) {
        const SurveyMap& m = maps[mi];
        std::vector<std::vector<double>> dist;  // per TrueInGrid: squared voxel distance to its solid
        for (const TrueInGrid& t : m.truths) dist.push_back(squaredDistanceToSet(m.grid, t.solid));
        for (std::size_t oi = 0; oi < m.objects.size(); ++oi) {
            Assignment a;
            a.map_index = static_cast<int>(mi);
            a.object_index = static_cast<int>(oi);
            for (std::size_t k = 0; k < m.truths.size(); ++k) {
                const int t = m.truths[k].true_index;
                if (t < 0 || t >= true_objects) continue;
                std::size_t n = 0;
                for (std::size_t v : m.objects[oi].voxels) n += dist[k][v] <= kWithinOneVoxelSq;
                if (n > a.overlap || (n == a.overlap && n > 0 && t < a.true_index)) {
                    a.overlap = n;
                    a.true_index = t;
                }
            }
            out.push_back(a);
        }
    }
    // Per true object: the largest overlap is the match, the rest duplicates.
    for (int t = 0; t < true_objects; ++t) {
        Assignment* best = nullptr;
        for (Assignment& a : out) {
            if (a.true_index != t) continue;
            a.role = MatchRole::Duplicate;
            if (!best) {
                best = &a;
                continue;
            }
            const auto key = [&](const Assignment& x) {
                return std::make_tuple(-static_cast<long long>(x.overlap), maps[x.map_index].map_id,
                                       maps[x.map_index].objects[x.object_index].id);
            };
            if (key(a) < key(*best)) best = &a;
        }
        if (best) best->role = MatchRole::Match;
    }
    return out;
}

SurveyScore scoreSurvey(const SurveyTruth& truth, const std::vector<SurveyMap>& maps) {
    SurveyScore s;
    const int n = static_cast<int>(truth.objects.size());
    s.truth = n;
    s.assignments = matchSurvey(maps, n);
    s.predicted = static_cast<int>(s.assignments.size());
    for (const Assignment& a : s.assignments) {
        if (a.role == MatchRole::Duplicate) ++s.duplicates;
        if (a.role != MatchRole::Match) ++s.false_detections;
    }
    for (int t = 0; t < n; ++t) {
        const SurveyTrueObject& o = truth.objects[t];
        ObjectScore os;
        os.true_index = t;
        os.name = o.name;
        os.true_centroid = 0.5 * (o.lo + o.hi);
        for (const Assignment& a : s.assignments)
            if (a.true_index == t && a.role == MatchRole::Duplicate) ++os.duplicates;
        for (const Assignment& a : s.assignments) {
            if (a.true_index != t || a.role != MatchRole::Match) continue;
            const SurveyMap& m = maps[a.map_index];
            const PredictedObject& p = m.objects[a.object_index];
            const TrueInGrid* g = nullptr;
            for (const TrueInGrid& x : m.truths)
                if (x.true_index == t) g = &x;
            if (!g) continue;  // cannot happen: a match overlaps the object in this grid
            os.found = true;
            os.map_id = m.map_id;
            os.object_id = p.id;
            os.overlap = a.overlap;
            os.clipped = g->clipped;
            VoxelMask predicted(m.grid.size(), 0);
            Eigen::Vector3d sum = Eigen::Vector3d::Zero();
            for (std::size_t v : p.voxels) {
                predicted[v] = 1;
                sum += m.grid.centre(v);
            }
            os.metrics = computeMetrics(m.grid, predicted, g->solid, g->visible);
            for (std::size_t k = 0; k < g->visible_by_run.size(); ++k)
                os.recall_by_run.emplace_back(truth.run_names[k], recallOn(m.grid, predicted, g->visible_by_run[k]));
            Eigen::Vector3d tsum = Eigen::Vector3d::Zero();
            std::size_t tn = 0;
            for (std::size_t i = 0; i < g->solid.size(); ++i)
                if (g->solid[i]) {
                    tsum += m.grid.centre(i);
                    ++tn;
                }
            if (tn > 0) os.true_centroid = tsum / static_cast<double>(tn);
            if (!p.voxels.empty()) {
                os.predicted_centroid = sum / static_cast<double>(p.voxels.size());
                os.centroid_error_m = (os.predicted_centroid - os.true_centroid).head<2>().norm();
            }
        }
        s.found += os.found;
        s.objects.push_back(std::move(os));
    }
    return s;
}

// ---------------------------------------------------------------- report

std::string surveyReportJson(const std::string& scenario, const SurveyScore& score, const std::vector<SurveyMap>& maps,
                             const NavigationReport& navigation) {
    json r;
    r["scenario"] = scenario;
    r["mode"] = "survey";
    r["detection"] = {{"true", score.truth},
                      {"found", score.found},
                      {"false", score.false_detections},
                      {"duplicates", score.duplicates},
                      {"predicted", score.predicted},
                      {"maps", maps.size()}};
    json objects = json::array();
    for (const ObjectScore& o : score.objects) {
        json j;
        j["true_id"] = o.true_index + 1;
        j["name"] = o.name;
        j["found"] = o.found;
        j["map_id"] = o.found ? json(o.map_id) : json(nullptr);
        j["object_id"] = o.found ? json(o.object_id) : json(nullptr);
        j["duplicates"] = o.duplicates;
        const Metrics& m = o.metrics;
        j["precision"] = optional(m.precision);
        j["recall_visible"] = optional(m.recall_visible);
        for (const auto& [run, recall] : o.recall_by_run) j["recall_visible_" + run] = optional(recall);
        j["chamfer_cm"] = optional(m.chamfer_cm);
        j["chamfer_pred_to_gt_cm"] = optional(m.chamfer_pred_to_gt_cm);
        j["chamfer_gt_to_pred_cm"] = optional(m.chamfer_gt_to_pred_cm);
        j["iou"] = optional(m.iou);
        j["false_volume_m3"] = optional(m.false_slope_m3);
        j["centroid_true"] = vecJson(o.true_centroid);
        j["centroid_predicted"] = o.found ? vecJson(o.predicted_centroid) : json(nullptr);
        j["centroid_error_m"] = o.found ? json(o.centroid_error_m) : json(nullptr);
        j["clipped_by_map"] = o.clipped;
        const VoxelCounts& c = m.counts;
        j["counts"] = {{"predicted_voxels", c.predicted},       {"predicted_correct_voxels", c.predicted_correct},
                       {"truth_voxels", c.truth},               {"intersection_voxels", c.intersection},
                       {"visible_surface_voxels", c.visible_surface}, {"recalled_voxels", c.recalled},
                       {"overlap_voxels", o.overlap}};
        objects.push_back(j);
    }
    r["objects"] = objects;
    json predicted = json::array();
    for (const Assignment& a : score.assignments) {
        const SurveyMap& m = maps[a.map_index];
        const PredictedObject& p = m.objects[a.object_index];
        predicted.push_back({{"map_id", m.map_id},
                             {"object_id", p.id},
                             {"voxels", p.voxels.size()},
                             {"centroid", vecJson(p.centroid)},
                             {"height_m", p.height_m},
                             {"ps_confirmed", p.ps_confirmed},
                             {"role", roleName(a.role)},
                             {"true_id", a.true_index >= 0 ? json(a.true_index + 1) : json(nullptr)},
                             {"overlap_voxels", a.overlap}});
    }
    r["predicted"] = predicted;
    json jm = json::array();
    for (const SurveyMap& m : maps) {
        json true_ids = json::array();
        for (const TrueInGrid& t : m.truths) true_ids.push_back(t.true_index + 1);
        jm.push_back({{"map_id", m.map_id},
                      {"map", m.map_path},
                      {"objects_file", m.objects_path.empty() ? json(nullptr) : json(m.objects_path)},
                      {"objects_source", m.objects_source},
                      {"variant", m.variant},
                      {"origin", vecJson(m.grid.origin)},
                      {"dims", {m.grid.nx, m.grid.ny, m.grid.nz}},
                      {"resolution", m.grid.resolution},
                      {"objects", m.objects.size()},
                      {"true_objects_in_grid", true_ids}});
    }
    r["maps"] = jm;
    if (navigation.asked) {
        if (!navigation.stats) r["navigation"] = nullptr;
        else {
            const NavErrorStats& n = *navigation.stats;
            r["navigation"] = {{"position_rms_m", n.position_rms_m},   {"position_max_m", n.position_max_m},
                               {"heading_rms_deg", n.heading_rms_deg}, {"heading_max_deg", n.heading_max_deg},
                               {"samples", n.samples},                 {"horizontal_rms_m", n.horizontal_rms_m},
                               {"horizontal_max_m", n.horizontal_max_m}, {"depth_rms_m", n.depth_rms_m},
                               {"attitude_rms_deg", n.attitude_rms_deg}, {"nav_unmatched", n.nav_unmatched},
                               {"truth_unmatched", n.truth_unmatched}};
        }
    }
    return r.dump(2) + "\n";
}

void writeSurveyReport(const std::string& path, const std::string& scenario, const SurveyScore& score,
                       const std::vector<SurveyMap>& maps, const NavigationReport& navigation) {
    const std::string text = surveyReportJson(scenario, score, maps, navigation);
    const std::string tmp = path + ".tmp";
    {
        std::ofstream out(tmp, std::ios::trunc);
        out << text;
        if (!out.flush()) throw std::runtime_error("report " + path + ": cannot write " + tmp);
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0) throw std::runtime_error("report " + path + ": rename failed");
}

std::vector<std::string> writeSurveyPointClouds(const std::string& dir, const std::vector<SurveyMap>& maps,
                                                const SurveyScore& score) {
    fs::create_directories(dir);
    std::vector<std::string> written;
    struct Point {
        Eigen::Vector3d p;
        int r, g, b;
    };
    const auto write = [&](const std::string& path, const std::vector<Point>& pts) {
        std::ofstream f(path, std::ios::trunc);
        f << "ply\nformat ascii 1.0\nelement vertex " << pts.size()
          << "\nproperty float x\nproperty float y\nproperty float z\n"
             "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n";
        for (const Point& q : pts) f << q.p.x() << ' ' << q.p.y() << ' ' << q.p.z() << ' ' << q.r << ' ' << q.g << ' ' << q.b << '\n';
        if (!f.flush()) throw std::runtime_error(path + ": cannot write");
        written.push_back(path);
    };
    for (std::size_t mi = 0; mi < maps.size(); ++mi) {
        const SurveyMap& m = maps[mi];
        std::vector<Point> pred, truth;
        for (const Assignment& a : score.assignments) {
            if (a.map_index != static_cast<int>(mi)) continue;
            const int r = a.role == MatchRole::Match ? 40 : 230, g = a.role == MatchRole::Match ? 200 : a.role == MatchRole::Duplicate ? 140 : 40;
            for (std::size_t v : m.objects[a.object_index].voxels) pred.push_back({m.grid.centre(v), r, g, 40});
        }
        for (const TrueInGrid& t : m.truths)
            for (std::size_t i = 0; i < t.solid.size(); ++i)
                if (t.solid[i]) truth.push_back({m.grid.centre(i), t.visible[i] ? 40 : 160, t.visible[i] ? 90 : 160, t.visible[i] ? 230 : 160});
        const std::string stem = (fs::path(dir) / ("survey_map_" + std::to_string(m.map_id))).string();
        write(stem + "_objects.ply", pred);
        write(stem + "_truth.ply", truth);
    }
    return written;
}

std::vector<std::string> writeSurveyFigures(const std::string& dir, const std::string& scenario,
                                            const SurveyTruth& truth, const std::vector<mesh::MeshSource>& seabed_meshes,
                                            const std::vector<SurveyMap>& maps, double occupied_probability) {
    std::vector<TriangleMesh> seabed;
    for (const auto& p : seabed_meshes) seabed.push_back(loadMesh(p));
    std::vector<std::string> written;
    for (const SurveyMap& m : maps) {
        const MapFileHeader h = readMapHeader(m.map_path);
        VoxelMap vm(mapConfigOf(h));
        loadMap(m.map_path, vm);
        const GridSpec& g = m.grid;
        Prediction pred;
        pred.object.assign(g.size(), 0);
        pred.occupied.assign(g.size(), 0);
        for (const PredictedObject& o : m.objects)
            for (std::size_t v : o.voxels) pred.object[v] = 1;
        for (std::size_t i = 0; i < g.size() && i < vm.size(); ++i) pred.occupied[i] = vm.occupancy(i) > occupied_probability;
        SceneTruth scene;  // only what lies in this map
        scene.name = scenario;
        GroundTruth gt;
        gt.grid = g;
        gt.object.solid.assign(g.size(), 0);
        gt.object.surface.assign(g.size(), 0);
        gt.visible.assign(g.size(), 0);
        for (const TrueInGrid& t : m.truths) {
            scene.objects.push_back(truth.objects[t.true_index].mesh);
            for (std::size_t i = 0; i < g.size(); ++i) {
                gt.object.solid[i] |= t.solid[i];
                gt.visible[i] |= t.visible[i];
            }
        }
        const Eigen::Vector3d lo = g.origin, hi = gridMax(g);
        for (const auto& s : seabed) scene.seabed.push_back(cropped(s, lo, hi));
        gt.seabed = voxeliseMeshes(scene.seabed, g);  // open pieces: crossed cells only, cheap
        const FigurePanel panel{m.variant.empty() ? "fused" : m.variant, &vm, &pred, &gt};
        for (auto& p : writeFigures((fs::path(dir) / ("map_" + std::to_string(m.map_id))).string(),
                                    scenario + " map " + std::to_string(m.map_id), scene, {panel}))
            written.push_back(std::move(p));
    }
    return written;
}

std::string surveyTable(const SurveyScore& score) {
    std::ostringstream o;
    std::size_t w = 6;
    for (const ObjectScore& x : score.objects) w = std::max(w, x.name.size());
    o << std::left << std::setw(static_cast<int>(w) + 2) << "object" << std::setw(7) << "found" << std::setw(9)
      << "map/obj" << std::right << std::setw(10) << "precision" << std::setw(12) << "recall_vis" << std::setw(12)
      << "recall_ps" << std::setw(12) << "chamfer_cm" << std::setw(14) << "centroid_err" << std::setw(6) << "dup"
      << "\n";
    for (const ObjectScore& x : score.objects) {
        std::optional<double> ps;
        for (const auto& [run, r] : x.recall_by_run)
            if (run == "ps") ps = r;
        const std::string where = x.found ? std::to_string(x.map_id) + "/" + std::to_string(x.object_id) : "-";
        o << std::left << std::setw(static_cast<int>(w) + 2) << x.name << std::setw(7) << (x.found ? "yes" : "NO")
          << std::setw(9) << where << std::right << std::setw(10) << cell(x.metrics.precision, 3) << std::setw(12)
          << cell(x.metrics.recall_visible, 3) << std::setw(12) << cell(ps, 3) << std::setw(12)
          << cell(x.metrics.chamfer_cm, 2) << std::setw(14)
          << (x.found ? cell(x.centroid_error_m, 2) + " m" : std::string("-")) << std::setw(6) << x.duplicates << "\n";
    }
    o << "detection: " << score.truth << " true, " << score.found << " found, " << score.false_detections
      << " false (" << score.duplicates << " of them duplicates), " << score.predicted << " predicted object(s)\n";
    return o.str();
}

}  // namespace sonarfusion::eval
