// Issue 12, "one config validator": each config struct's own validate()
// (config.hpp) names the key of a bad value, MapperConfig::validate() names it
// in full, and the Mapper constructor refuses the config with that key. The
// command-line side (file and key named, exit 2) is tests/mapperd/test_config_cli.cpp.
#include <gtest/gtest.h>

#include <functional>
#include <stdexcept>
#include <string>

#include "sonarfusion/config.hpp"
#include "sonarfusion/mapper.hpp"

namespace sonarfusion {
namespace {

struct BadValue {
    const char* name;  // test name: the struct and the value
    std::function<void(MapperConfig&)> spoil;
    const char* key;  // the full key MapperConfig::validate() must name
};

void PrintTo(const BadValue& b, std::ostream* os) { *os << b.key; }

const BadValue kBadValues[] = {
    {"Fls_beams0", [](MapperConfig& c) { c.fls.beams = 0; }, "fls.beams"},
    {"Fls_rows1", [](MapperConfig& c) { c.fls.rows = 1; }, "fls.rows"},
    // FlsModel allocates up to 256 elevation samples; validateConfig used to let 1024 through.
    {"Fls_elevation_samples500", [](MapperConfig& c) { c.fls.elevation_samples = 500; }, "fls.elevation_samples"},
    {"Fls_elevation_flat", [](MapperConfig& c) { c.fls.elevation_max = c.fls.elevation_min; }, "fls.elevation_max_deg"},
    {"Fls_range_min_negative", [](MapperConfig& c) { c.fls.range_min = -1.0; }, "fls.range_min"},
    {"Fls_range_max_inf", [](MapperConfig& c) { c.fls.range_max = INFINITY; }, "fls.range_max"},
    {"Fls_fov_zero", [](MapperConfig& c) { c.fls.fov_horizontal = 0.0; }, "fls.fov_horizontal_deg"},
    {"Fls_bearing_count", [](MapperConfig& c) { c.fls.beam_bearing.assign(3, 0.0); }, "fls.beam_bearing_deg"},
    {"Fls_row_range_nan", [](MapperConfig& c) { c.fls.row_range.assign(c.fls.rows, NAN); }, "fls.row_range"},
    {"FlsMount_x_nan", [](MapperConfig& c) { c.fls_mount.x = NAN; }, "fls.mount.x"},
    {"PsMount_yaw_inf", [](MapperConfig& c) { c.ps_mount.yaw = INFINITY; }, "ps.mount.yaw_deg"},
    {"Ps_bins1", [](MapperConfig& c) { c.ps.bins = 1; }, "ps.bins"},
    {"Ps_fan_reversed", [](MapperConfig& c) { c.ps.fan_max = c.ps.fan_min - 0.1; }, "ps.fan_max_deg"},
    {"Ps_head_reversed", [](MapperConfig& c) { c.ps.head_max = c.ps.head_min - 0.1; }, "ps.head_max_deg"},
    {"Ps_fan_samples0", [](MapperConfig& c) { c.ps.fan_samples = 0; }, "ps.fan_samples"},
    {"Ps_beam_width_negative", [](MapperConfig& c) { c.ps.beam_width_vertical = -0.01; }, "ps.beam_width_vertical_deg"},
    {"Ps_beam_width_nan", [](MapperConfig& c) { c.ps.beam_width_vertical = NAN; }, "ps.beam_width_vertical_deg"},
    {"Map_nx0", [](MapperConfig& c) { c.map.nx = 0; }, "map.nx"},
    {"Map_ny5000", [](MapperConfig& c) { c.map.ny = 5000; }, "map.ny"},
    {"Map_nz_negative", [](MapperConfig& c) { c.map.nz = -1; }, "map.nz"},
    {"Map_resolution0", [](MapperConfig& c) { c.map.resolution = 0.0; }, "map.resolution"},
    {"Map_clamp_min_positive", [](MapperConfig& c) { c.map.clamp_min = 1.0f; }, "map.clamp_min"},
    {"Map_clamp_max_nan", [](MapperConfig& c) { c.map.clamp_max = NAN; }, "map.clamp_max"},
    {"Update_p_free", [](MapperConfig& c) { c.update.p_free = 0.7; }, "update.p_free"},
    {"Update_p_occupied", [](MapperConfig& c) { c.update.p_occupied = 0.4; }, "update.p_occupied"},
    {"Update_alpha_fls", [](MapperConfig& c) { c.update.alpha_fls = 0.0; }, "update.alpha_fls"},
    {"Update_fls_free_vote_ratio", [](MapperConfig& c) { c.update.fls_free_vote_ratio = 0.0; }, "update.fls_free_vote_ratio"},
    {"Update_fls_noise_sigmas", [](MapperConfig& c) { c.update.fls_free_space_noise_sigmas = -1.0; },
     "update.fls_free_space_noise_sigmas"},
    {"Update_ps_noise_sigmas_nan", [](MapperConfig& c) { c.update.ps_carve_noise_sigmas = NAN; },
     "update.ps_carve_noise_sigmas"},
    {"Segmentation_raised_sigmas_nan", [](MapperConfig& c) { c.segmentation.seabed_raised_sigmas = NAN; },
     "segmentation.seabed_raised_sigmas"},
    {"Update_ps_echo_window_negative", [](MapperConfig& c) { c.update.ps_carve_echo_window_voxels = -1.0; },
     "update.ps_carve_echo_window_voxels"},
    {"Update_spare_share_above_one", [](MapperConfig& c) { c.update.ps_carve_spare_echo_share = 1.5; },
     "update.ps_carve_spare_echo_share"},
    {"Update_spare_share_nan", [](MapperConfig& c) { c.update.ps_carve_spare_echo_share = NAN; },
     "update.ps_carve_spare_echo_share"},
    {"Update_spare_min_echoes0", [](MapperConfig& c) { c.update.ps_carve_spare_min_echoes = 0; },
     "update.ps_carve_spare_min_echoes"},
    {"Update_spare_min_echoes64", [](MapperConfig& c) { c.update.ps_carve_spare_min_echoes = 64; },
     "update.ps_carve_spare_min_echoes"},
    {"Update_threshold", [](MapperConfig& c) { c.update.fls_intensity_threshold = 256; },
     "update.fls_intensity_threshold"},
    {"Update_arc_spacing", [](MapperConfig& c) { c.update.fls_arc_spacing_voxels = 1e-6; },
     "update.fls_arc_spacing_voxels"},
    {"PsSelection_tau", [](MapperConfig& c) { c.ps_selection.group_threshold = 1.0; }, "ps_selection.group_threshold"},
    {"PsSelection_min_range", [](MapperConfig& c) { c.ps_selection.min_range = NAN; }, "ps_selection.min_range"},
    {"PsSelection_peak", [](MapperConfig& c) { c.ps_selection.min_peak_intensity = -1; },
     "ps_selection.min_peak_intensity"},
    {"Detector_radius", [](MapperConfig& c) { c.detector.seabed_radius = 0.0; }, "detector.seabed_radius"},
    {"Detector_nearest_sigmas_negative", [](MapperConfig& c) { c.detector.nearest_echo_sigmas = -1.0; },
     "detector.nearest_echo_sigmas"},
    {"Detector_shadow_false_alarm", [](MapperConfig& c) { c.detector.fls_shadow_false_alarm = -1e-5; },
     "detector.fls_shadow_false_alarm"},
    {"Detector_shadow_min_frames", [](MapperConfig& c) { c.detector.fls_shadow_min_frames = 0; },
     "detector.fls_shadow_min_frames"},
    // The detector's constructor needs min_rise > 0 and at most 2^16 risen echoes;
    // validateConfig used to accept 0 and 10^6 (sf-mapper then exited 1, no key).
    {"Detector_min_rise0", [](MapperConfig& c) { c.detector.min_rise = 0.0; }, "detector.min_rise"},
    {"Detector_risen_capacity", [](MapperConfig& c) { c.detector.risen_capacity = 100000; }, "detector.risen_capacity"},
    {"Detector_min_seabed_echoes", [](MapperConfig& c) { c.detector.min_seabed_echoes = 2000; },
     "detector.min_seabed_echoes"},
    {"Segmentation_max_objects0", [](MapperConfig& c) { c.segmentation.max_objects = 0; }, "segmentation.max_objects"},
    {"Segmentation_occupied", [](MapperConfig& c) { c.segmentation.occupied_probability = 1.0; },
     "segmentation.occupied_probability"},
    {"Segmentation_window", [](MapperConfig& c) { c.segmentation.baseline_window = 0.0; },
     "segmentation.baseline_window"},
    {"Segmentation_extension", [](MapperConfig& c) { c.segmentation.fls_only_extension = 1000; },
     "segmentation.fls_only_extension"},
    {"Segmentation_votes_per_crossing_negative",
     [](MapperConfig& c) { c.segmentation.fls_votes_per_ps_crossing = -1.0; }, "segmentation.fls_votes_per_ps_crossing"},
    {"Segmentation_votes_per_crossing_inf",
     [](MapperConfig& c) { c.segmentation.fls_votes_per_ps_crossing = INFINITY; },
     "segmentation.fls_votes_per_ps_crossing"},
    {"Survey_max_maps0", [](MapperConfig& c) { c.survey.max_maps = 0; }, "survey.max_maps"},
    {"Survey_release_margin_nan", [](MapperConfig& c) { c.survey.release_margin = NAN; }, "survey.release_margin"},
    {"Nav_max_gap0", [](MapperConfig& c) { c.max_nav_gap_us = 0; }, "nav.max_gap_us"},
    {"Nav_buffer1", [](MapperConfig& c) { c.nav_buffer_capacity = 1; }, "nav.buffer_capacity"},
    {"Nav_confirm0", [](MapperConfig& c) { c.nav_timeline_confirm = 0; }, "nav.timeline_confirm"},
    {"Survey_max_maps65", [](MapperConfig& c) { c.survey.max_maps = 65; }, "survey.max_maps"},
    {"Survey_published0", [](MapperConfig& c) { c.survey.published_capacity = 0; }, "survey.published_capacity"},
};

class ConfigValidate : public ::testing::TestWithParam<BadValue> {};

TEST_P(ConfigValidate, NamesTheKeyAndTheMapperRefusesIt) {
    const BadValue& b = GetParam();
    MapperConfig c;
    b.spoil(c);
    const std::optional<ConfigIssue> issue = c.validate();
    ASSERT_TRUE(issue.has_value()) << b.key << " accepted";
    EXPECT_EQ(issue->key, b.key);
    EXPECT_FALSE(issue->reason.empty());
    EXPECT_EQ(validateConfig(c), issue->message());
    try {
        Mapper m(c);
        ADD_FAILURE() << "Mapper accepted a bad " << b.key;
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find(std::string(b.key) + ": "), std::string::npos) << e.what();
    }
}

INSTANTIATE_TEST_SUITE_P(EveryStruct, ConfigValidate, ::testing::ValuesIn(kBadValues),
                         [](const ::testing::TestParamInfo<BadValue>& i) { return std::string(i.param.name); });

// Each struct's own validate() gives the key relative to its block; the
// block name is added by whoever holds it.
TEST(ConfigValidateBlocks, EachStructNamesItsOwnKey) {
    EXPECT_FALSE(MapperConfig{}.validate().has_value());
    MapConfig map;
    EXPECT_FALSE(map.validate().has_value());
    map.nz = 0;
    ASSERT_TRUE(map.validate().has_value());
    EXPECT_EQ(map.validate()->key, "nz");
    EXPECT_EQ(map.validate()->in("map").key, "map.nz");
    Mounting mount;
    mount.roll = NAN;
    ASSERT_TRUE(mount.validate().has_value());
    EXPECT_EQ(mount.validate()->in("ps.mount").key, "ps.mount.roll_deg");
    DetectorConfig det;
    det.cluster_radius = -1.0;
    ASSERT_TRUE(det.validate().has_value());
    EXPECT_EQ(det.validate()->key, "cluster_radius");
}

// What validate() accepts, the constructors it stands for accept: the limits
// are the constructors' own (elevation samples 256, risen echoes 2^16).
TEST(ConfigValidateBlocks, TheLimitsAreTheConstructorsLimits) {
    MapperConfig c;
    c.map.nx = c.map.ny = c.map.nz = 8;
    c.fls.elevation_samples = 256;
    c.detector.risen_capacity = 65536;
    c.detector.min_rise = 1e-9;
    c.ps.head_min = c.ps.head_max;  // a fixed head: allowed
    ASSERT_FALSE(c.validate().has_value()) << c.validate()->message();
    EXPECT_NO_THROW(Mapper m(c));
    c.fls.elevation_samples = 257;
    EXPECT_EQ(c.validate()->key, "fls.elevation_samples");
}

}  // namespace
}  // namespace sonarfusion
