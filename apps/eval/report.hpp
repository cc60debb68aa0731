// report.json (DESIGN.md §7) and the side-by-side table on stdout.
//
// {"scenario": NAME, "variants": {"fls_only": M, "carve_only": M, "paper": M, "fused": M}}
// M = {precision, recall_visible, iou, chamfer_cm, false_slope_m3, face_angle_deg,
//      (null where undefined) plus recall_visible_<run>, chamfer_pred_to_gt_cm,
//      chamfer_gt_to_pred_cm, face_angle_true_deg, face_angles_deg, map, counts{...}}
#pragma once

#include <string>
#include <vector>

#include "map_scoring.hpp"

namespace sonarfusion::eval {

// The report as JSON text. With `merge_into` naming an existing report, its
// other variants and any extra keys of a scored variant's M (e.g. message
// counts added by tools/mission) are kept.
[[nodiscard]] std::string reportJson(const std::string& scenario, const std::vector<VariantScore>& scores,
                                     const std::string& merge_into = "");
// Writes atomically (temp file + rename). Throws std::runtime_error on failure.
void writeReport(const std::string& path, const std::string& scenario, const std::vector<VariantScore>& scores,
                 bool merge);

[[nodiscard]] std::string scoreTable(const std::vector<VariantScore>& scores);

}  // namespace sonarfusion::eval
