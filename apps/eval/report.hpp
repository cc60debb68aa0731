// report.json (docs/design.md, "Entry points") and the side-by-side table on stdout.
//
// {"scenario": NAME, "variants": {"fls_only": M, "carve_only": M, "paper": M, "fused": M},
//  "navigation": N}   (only with sf-eval --log; null when the log has no NAV_TRUTH)
// M = {precision, recall_visible, iou, chamfer_cm, false_slope_m3, face_angle_deg,
//      (null where undefined) plus recall_visible_<run>, chamfer_pred_to_gt_cm,
//      chamfer_gt_to_pred_cm, face_angle_true_deg, face_angles_deg, map, counts{...}}
// N = {position_rms_m, position_max_m, heading_rms_deg, heading_max_deg, samples,
//      horizontal_rms_m, horizontal_max_m, depth_rms_m, attitude_rms_deg,
//      nav_unmatched, truth_unmatched}
#pragma once

#include <string>
#include <vector>

#include "map_scoring.hpp"
#include "nav_error.hpp"

namespace sonarfusion::eval {

// The report as JSON text. With `merge_into` naming an existing report, its
// other variants and any extra keys of a scored variant's M (e.g. message
// counts added by tools/mission) are kept. `navigation` sets the top-level
// "navigation" key when asked (an object, or null without statistics).
[[nodiscard]] std::string reportJson(const std::string& scenario, const std::vector<VariantScore>& scores,
                                     const std::string& merge_into = "", const NavigationReport& navigation = {});
// Writes atomically (temp file + rename). Throws std::runtime_error on failure.
void writeReport(const std::string& path, const std::string& scenario, const std::vector<VariantScore>& scores,
                 bool merge, const NavigationReport& navigation = {});

[[nodiscard]] std::string scoreTable(const std::vector<VariantScore>& scores);

}  // namespace sonarfusion::eval
