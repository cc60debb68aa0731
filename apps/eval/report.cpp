#include "report.hpp"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

namespace sonarfusion::eval {

namespace {
using nlohmann::json;

json optional(const std::optional<double>& v) { return v ? json(*v) : json(nullptr); }

json variantJson(const VariantScore& s) {
    const Metrics& m = s.metrics;
    json j;
    j["precision"] = optional(m.precision);
    j["recall_visible"] = optional(m.recall_visible);
    j["iou"] = optional(m.iou);
    j["chamfer_cm"] = optional(m.chamfer_cm);
    j["false_slope_m3"] = optional(m.false_slope_m3);
    j["face_angle_deg"] = optional(s.face_angle_deg);
    for (const auto& [run, recall] : s.recall_by_run) j["recall_visible_" + run] = optional(recall);
    j["chamfer_pred_to_gt_cm"] = optional(m.chamfer_pred_to_gt_cm);
    j["chamfer_gt_to_pred_cm"] = optional(m.chamfer_gt_to_pred_cm);
    j["face_angle_true_deg"] = optional(s.true_face_angle_deg);
    json faces = json::array();
    for (const FaceAngle& f : s.faces) faces.push_back(optional(f.angle_deg));
    j["face_angles_deg"] = faces;
    j["map"] = s.map_path;
    if (s.missed)
        j["missed_visible"] = {{"free_with_ps_echoes", s.missed->free_with_ps_echoes},
                               {"free", s.missed->free},
                               {"not_occupied", s.missed->not_occupied},
                               {"occupied_ps_observed", s.missed->occupied_ps_observed},
                               {"occupied_outside_ps", s.missed->occupied_outside_ps}};
    const VoxelCounts& c = m.counts;
    j["counts"] = {{"predicted_voxels", c.predicted},
                   {"predicted_correct_voxels", c.predicted_correct},
                   {"truth_voxels", c.truth},
                   {"intersection_voxels", c.intersection},
                   {"visible_surface_voxels", c.visible_surface},
                   {"recalled_voxels", c.recalled},
                   {"occupied_voxels", s.segmentation.occupied_voxels},
                   {"unconfirmed_voxels", s.segmentation.unconfirmed_voxels},
                   {"objects", s.objects},
                   {"objects_true", s.objects_true}};
    json face_points = json::array();
    for (const FaceAngle& f : s.faces) face_points.push_back(f.points);
    j["counts"]["face_fit_voxels"] = face_points;
    return j;
}

json navigationJson(const NavigationReport& r) {
    if (!r.stats) return json(nullptr);
    const NavErrorStats& s = *r.stats;
    json j;
    j["position_rms_m"] = s.position_rms_m;
    j["position_max_m"] = s.position_max_m;
    j["heading_rms_deg"] = s.heading_rms_deg;
    j["heading_max_deg"] = s.heading_max_deg;
    j["samples"] = s.samples;
    j["horizontal_rms_m"] = s.horizontal_rms_m;
    j["horizontal_max_m"] = s.horizontal_max_m;
    j["depth_rms_m"] = s.depth_rms_m;
    j["attitude_rms_deg"] = s.attitude_rms_deg;
    j["nav_unmatched"] = s.nav_unmatched;
    j["truth_unmatched"] = s.truth_unmatched;
    return j;
}

std::string cell(const std::optional<double>& v, int precision) {
    if (!v) return "null";
    std::ostringstream o;
    o << std::fixed << std::setprecision(precision) << *v;
    return o.str();
}
}  // namespace

std::string reportJson(const std::string& scenario, const std::vector<VariantScore>& scores,
                       const std::string& merge_into, const NavigationReport& navigation) {
    json report;
    if (!merge_into.empty() && std::filesystem::exists(merge_into)) {
        std::ifstream in(merge_into);
        try {
            report = json::parse(in);
        } catch (const json::exception& e) {
            throw std::runtime_error("report " + merge_into + ": cannot merge, not JSON: " + e.what());
        }
    }
    report["scenario"] = scenario;
    if (!report.contains("variants") || !report["variants"].is_object()) report["variants"] = json::object();
    for (const VariantScore& s : scores) {
        json& m = report["variants"][s.variant];
        if (!m.is_object()) m = json::object();
        m.update(variantJson(s));
    }
    if (navigation.asked) report["navigation"] = navigationJson(navigation);
    return report.dump(2) + "\n";
}

void writeReport(const std::string& path, const std::string& scenario, const std::vector<VariantScore>& scores,
                 bool merge, const NavigationReport& navigation) {
    const std::string text = reportJson(scenario, scores, merge ? path : "", navigation);
    const std::string tmp = path + ".tmp";
    {
        std::ofstream out(tmp, std::ios::trunc);
        out << text;
        if (!out.flush()) throw std::runtime_error("report " + path + ": cannot write " + tmp);
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0) throw std::runtime_error("report " + path + ": rename failed");
}

std::string scoreTable(const std::vector<VariantScore>& scores) {
    std::ostringstream o;
    const int w = 12;
    o << std::left << std::setw(24) << "metric";
    for (const auto& s : scores) o << std::right << std::setw(w) << s.variant;
    o << '\n';
    auto row = [&](const std::string& name, auto get, int precision) {
        o << std::left << std::setw(24) << name;
        for (const auto& s : scores) o << std::right << std::setw(w) << cell(get(s), precision);
        o << '\n';
    };
    using Opt = std::optional<double>;
    row("precision", [](const VariantScore& s) { return s.metrics.precision; }, 3);
    row("recall_visible", [](const VariantScore& s) { return s.metrics.recall_visible; }, 3);
    if (!scores.empty())
        for (std::size_t k = 0; k < scores.front().recall_by_run.size(); ++k)
            row("recall_visible_" + scores.front().recall_by_run[k].first,
                [k](const VariantScore& s) { return k < s.recall_by_run.size() ? s.recall_by_run[k].second : Opt(); }, 3);
    row("iou", [](const VariantScore& s) { return s.metrics.iou; }, 3);
    row("chamfer_cm", [](const VariantScore& s) { return s.metrics.chamfer_cm; }, 2);
    row("  pred->gt cm", [](const VariantScore& s) { return s.metrics.chamfer_pred_to_gt_cm; }, 2);
    row("  gt->pred cm", [](const VariantScore& s) { return s.metrics.chamfer_gt_to_pred_cm; }, 2);
    row("false_slope_m3", [](const VariantScore& s) { return s.metrics.false_slope_m3; }, 3);
    row("face_angle_deg", [](const VariantScore& s) { return s.face_angle_deg; }, 1);
    row("face_angle_true_deg", [](const VariantScore& s) { return s.true_face_angle_deg; }, 1);
    row("predicted_voxels", [](const VariantScore& s) { return Opt(static_cast<double>(s.metrics.counts.predicted)); }, 0);
    // Why the missed visible voxels were missed (map_scoring.hpp, MissedVisible).
    auto missed = [&](const std::string& name, std::size_t MissedVisible::*field) {
        row(name, [field](const VariantScore& s) { return s.missed ? Opt(static_cast<double>((*s.missed).*field)) : Opt(); }, 0);
    };
    if (!scores.empty() && scores.front().missed) {
        missed("missed: free, PS echo", &MissedVisible::free_with_ps_echoes);
        missed("missed: free", &MissedVisible::free);
        missed("missed: not occupied", &MissedVisible::not_occupied);
        missed("missed: occ., PS seen", &MissedVisible::occupied_ps_observed);
        missed("missed: occ., no PS", &MissedVisible::occupied_outside_ps);
    }
    row("objects", [](const VariantScore& s) { return Opt(static_cast<double>(s.objects)); }, 0);
    row("objects_true", [](const VariantScore& s) { return Opt(static_cast<double>(s.objects_true)); }, 0);
    return o.str();
}

}  // namespace sonarfusion::eval
