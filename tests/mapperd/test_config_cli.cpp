// Issue 12: every bad value of a config file stops sf-mapper with exit code 2
// and a message naming the file and the key ("FILE: map.nx: must be in
// 1..4096"), one case (or more) per config struct, the daemon's included.
// Before issue 12, map.nx's message named "map.nx/ny/nz", and fls.elevation_samples,
// detector.min_rise and detector.risen_capacity passed validation and made
// sf-mapper exit 1 from a constructor, naming neither file nor key.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace {

namespace fs = std::filesystem;

struct BadFile {
    const char* name;  // test name: the struct and the value
    const char* yaml;
    const char* key;  // the key the message must name, after the file
};

void PrintTo(const BadFile& b, std::ostream* os) { *os << b.yaml; }

const BadFile kBadFiles[] = {
    // FlsGeometry
    {"Fls_beams0", "fls: {beams: 0}", "fls.beams"},
    {"Fls_elevation_samples500", "fls: {elevation_samples: 500}", "fls.elevation_samples"},
    {"Fls_elevation_flat", "fls: {elevation_min_deg: 7, elevation_max_deg: 7}", "fls.elevation_max_deg"},
    {"Fls_bearings_per_beam", "fls: {beams: 2, beam_bearing_deg: [1.0]}", "fls.beam_bearing_deg"},
    {"Fls_not_a_number", "fls: {range_max: far}", "fls.range_max"},
    // Mounting
    {"FlsMount_x_nan", "fls: {mount: {x: .nan}}", "fls.mount.x"},
    {"PsMount_unknown", "ps: {mount: {pitch_deg: 3}}", "ps.mount.pitch_deg"},
    // PsGeometry
    {"Ps_bins1", "ps: {bins: 1}", "ps.bins"},
    {"Ps_fan_reversed", "ps: {fan_min_deg: 10, fan_max_deg: -10}", "ps.fan_max_deg"},
    {"Ps_range_max_inf", "ps: {range_max: .inf}", "ps.range_max"},
    // MapConfig
    {"Map_nx0", "map: {nx: 0}", "map.nx"},
    {"Map_ny5000", "map: {ny: 5000}", "map.ny"},
    {"Map_resolution0", "map: {resolution: 0}", "map.resolution"},
    {"Map_clamp_min_positive", "map: {clamp_min: 1}", "map.clamp_min"},
    // UpdateConfig
    {"Update_p_free", "update: {p_free: 0.7}", "update.p_free"},
    {"Update_threshold", "update: {fls_intensity_threshold: 300}", "update.fls_intensity_threshold"},
    // PsSelectionConfig
    {"PsSelection_tau", "ps_selection: {group_threshold: 1.5}", "ps_selection.group_threshold"},
    // DetectorConfig
    {"Detector_min_rise0", "detector: {min_rise: 0}", "detector.min_rise"},
    {"Detector_risen_capacity", "detector: {risen_capacity: 100000}", "detector.risen_capacity"},
    // Removed in issue 12 (nothing read it): an unknown key, as every unknown key is.
    {"Detector_max_range_fraction", "detector: {max_range_fraction: 0.98}", "detector.max_range_fraction"},
    // SegmentationConfig
    {"Segmentation_max_objects0", "segmentation: {max_objects: 0}", "segmentation.max_objects"},
    {"Segmentation_occupied", "segmentation: {occupied_probability: 1}", "segmentation.occupied_probability"},
    // MapperConfig's own (nav)
    {"Nav_max_gap0", "nav: {max_gap_us: 0}", "nav.max_gap_us"},
    {"Nav_confirm0", "nav: {timeline_confirm: 0}", "nav.timeline_confirm"},
    {"Survey_max_maps0", "survey: {max_maps: 0}", "survey.max_maps"},
    {"Fls_max_geometries0", "fls: {max_geometries: 0}", "fls.max_geometries"},
    {"Fls_max_geometries65", "fls: {max_geometries: 65}", "fls.max_geometries"},
    {"Survey_release_margin_inf", "survey: {release_margin: .inf}", "survey.release_margin"},
    // DaemonConfig
    {"Daemon_queue0", "daemon: {queue_capacity: 0}", "daemon.queue_capacity"},
    {"Daemon_memory", "map: {nx: 4096, ny: 4096, nz: 64}", "daemon.memory_budget_mb"},
    {"Channels_same", "channels: {fls: NAV}", "channels.fls"},
    {"Variant_unknown", "variant: best", "variant"},
    {"Top_level_unknown", "mapp: {nx: 10}", "mapp"},
};

struct CliRun {
    int exit_code;
    std::string err;
};

std::string readFile(const std::string& path) {
    std::ifstream in(path);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

class MapperConfigCli : public ::testing::TestWithParam<BadFile> {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() / ("sf_config_cli_" + std::to_string(::getpid()) + "_" + GetParam().name);
        fs::create_directories(dir_);
        std::ofstream(dir_ / "empty.lcmlog").flush();
    }
    void TearDown() override { fs::remove_all(dir_); }

    CliRun mapper(const std::string& config) const {
        const std::string err = (dir_ / "output.txt").string();
        const std::string cmd = std::string(SF_MAPPER_EXE) + " --quiet --config " + config + " --log " +
                                (dir_ / "empty.lcmlog").string() + " --map-out " + (dir_ / "x.map").string() + " > " +
                                err + " 2>&1";  // spdlog writes to stdout
        const int status = std::system(cmd.c_str());
        return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, readFile(err)};
    }
    std::string write(const std::string& name, const std::string& yaml) const {
        const std::string path = (dir_ / name).string();
        std::ofstream(path) << yaml << "\n";
        return path;
    }

    fs::path dir_;
};

TEST_P(MapperConfigCli, BadValueNamesFileAndKeyExitTwo) {
    const BadFile& b = GetParam();
    const std::string path = write("bad.yaml", b.yaml);
    const CliRun r = mapper(path);
    EXPECT_EQ(r.exit_code, 2) << b.yaml << "\n" << r.err;
    // "FILE: KEY: reason" (or "FILE: KEY: unknown key").
    EXPECT_NE(r.err.find(path + ": " + b.key + ": "), std::string::npos) << b.yaml << "\n" << r.err;
}

INSTANTIATE_TEST_SUITE_P(EveryStruct, MapperConfigCli, ::testing::ValuesIn(kBadFiles),
                         [](const ::testing::TestParamInfo<BadFile>& i) { return std::string(i.param.name); });

// The control: the same command line with good files maps (exit 0), so the
// cases above fail on their value, not on the command.
TEST(MapperConfigCliControl, GoodFilesExitZero) {
    const fs::path dir = fs::temp_directory_path() / ("sf_config_cli_ok_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    std::ofstream(dir / "empty.lcmlog").flush();
    for (const char* yaml : {"map: {nx: 64}", "fls: {mount: {x: 0.1, yaw_deg: 0}}", "detector: {min_rise: 0.05}",
                             "fls: {elevation_samples: 256}", "segmentation: {max_objects: 1}"}) {
        const std::string path = (dir / "ok.yaml").string();
        std::ofstream(path) << yaml << "\n";
        const std::string cmd = std::string(SF_MAPPER_EXE) + " --quiet --config " + path + " --log " +
                                (dir / "empty.lcmlog").string() + " --map-out " + (dir / "x.map").string() + " 2> " +
                                (dir / "err.txt").string();
        const int status = std::system(cmd.c_str());
        EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << yaml << "\n"
                                                                   << readFile((dir / "err.txt").string());
    }
    // The reference config, which has every section.
    const std::string cmd = std::string(SF_MAPPER_EXE) + " --quiet --config " + SF_SOURCE_DIR +
                            "/scenarios/mapper.yaml --log " + (dir / "empty.lcmlog").string() + " --map-out " +
                            (dir / "x.map").string();
    EXPECT_EQ(std::system(cmd.c_str()), 0);
    fs::remove_all(dir);
}

}  // namespace
