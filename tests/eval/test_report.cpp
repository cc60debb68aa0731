// report.json format (docs/design.md, "Entry points") and the merge of several runs into one file.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "eval_test_helpers.hpp"
#include "report.hpp"

namespace sonarfusion::eval {
namespace {

VariantScore score(const std::string& variant, std::optional<double> precision) {
    VariantScore s;
    s.variant = variant;
    s.metrics.precision = precision;
    s.metrics.recall_visible = 0.5;
    s.metrics.counts.predicted = 42;
    s.recall_by_run = {{"fls", 0.25}, {"ps", std::nullopt}};
    s.faces = {FaceAngle{88.0, 90.0, 10}, FaceAngle{std::nullopt, 90.0, 0}};
    s.face_angle_deg = 88.0;
    return s;
}

TEST(Report, HasDesignKeysWithNulls) {
    const auto j = nlohmann::json::parse(reportJson("slope_box_90", {score("fused", 0.9), score("fls_only", std::nullopt)}));
    EXPECT_EQ(j["scenario"], "slope_box_90");
    for (const char* v : {"fused", "fls_only"}) {
        const auto& m = j["variants"][v];
        for (const char* key : {"precision", "recall_visible", "iou", "chamfer_cm", "false_slope_m3", "face_angle_deg"})
            EXPECT_TRUE(m.contains(key)) << v << "." << key;
        EXPECT_EQ(m["counts"]["predicted_voxels"], 42);
        EXPECT_TRUE(m["iou"].is_null());
        EXPECT_TRUE(m["recall_visible_ps"].is_null());
        EXPECT_DOUBLE_EQ(m["recall_visible_fls"].get<double>(), 0.25);
        EXPECT_TRUE(m["face_angles_deg"][1].is_null());
    }
    EXPECT_DOUBLE_EQ(j["variants"]["fused"]["precision"].get<double>(), 0.9);
    EXPECT_TRUE(j["variants"]["fls_only"]["precision"].is_null());
}

TEST(Report, MergeKeepsOtherVariantsAndExtraKeys) {
    const std::string path = test::tempDir() + "/report_merge.json";
    std::ofstream(path) << R"({"scenario": "x", "variants": {"paper": {"precision": 0.3},
                              "fused": {"messages": {"FLS": 800}, "precision": 0.1}}})";
    writeReport(path, "slope_box_90", {score("fused", 0.9)}, true);
    std::ifstream in(path);
    const auto j = nlohmann::json::parse(in);
    EXPECT_EQ(j["scenario"], "slope_box_90");
    EXPECT_DOUBLE_EQ(j["variants"]["paper"]["precision"].get<double>(), 0.3);
    EXPECT_DOUBLE_EQ(j["variants"]["fused"]["precision"].get<double>(), 0.9);
    EXPECT_EQ(j["variants"]["fused"]["messages"]["FLS"], 800);
}

TEST(Report, TableHasOneColumnPerVariant) {
    const std::string t = scoreTable({score("fls_only", 0.5), score("fused", 0.9)});
    EXPECT_NE(t.find("fls_only"), std::string::npos);
    EXPECT_NE(t.find("0.900"), std::string::npos);
    EXPECT_NE(t.find("recall_visible_ps"), std::string::npos);
}

}  // namespace
}  // namespace sonarfusion::eval
