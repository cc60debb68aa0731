// sf-eval: scores saved maps against the scenario's meshes (docs/design.md,
// "Evaluation" and "Entry points").
//   sf-eval --scenario FILE --map MAP --json OUT.json --figures DIR
//   sf-eval --scenario FILE --map fls_only=A.map --map fused=B.map ... (side by side)
//   sf-eval --scenario FILE --maps-dir DIR   (every readable map file in DIR)
//   sf-eval ... --log RUN.lcmlog   (also: how far NAV was from NAV_TRUTH over the run)
//   sf-eval --scenario FILE --map-dir DIR --json OUT.json   (a survey: sf-mapper --map-dir's
//           map_<k>.map + map_<k>.objects.json, every true object against every published one)
#include <CLI/CLI.hpp>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>

#include "figures.hpp"
#include "mapper_config_yaml.hpp"  // the reader sf-mapper uses (sf_config_yaml)
#include "ground_truth.hpp"
#include "map_file.hpp"
#include "map_scoring.hpp"
#include "nav_error.hpp"
#ifdef SF_EVAL_NAV_LOG
#include "nav_log.hpp"
#endif
#include "report.hpp"
#include "scenario_source.hpp"
#include "survey.hpp"

namespace fs = std::filesystem;
using namespace sonarfusion;
using namespace sonarfusion::eval;

namespace {

struct MapInput {
    std::string variant;  // empty: take it from the map file's header
    std::string path;
};

MapInput parseMapArgument(const std::string& arg) {
    const auto eq = arg.find('=');
    if (eq != std::string::npos && parseVariant(arg.substr(0, eq))) return {arg.substr(0, eq), arg.substr(eq + 1)};
    return {"", arg};
}

std::vector<MapInput> mapsInDir(const std::string& dir) {
    std::vector<MapInput> found;
    for (const auto& e : fs::directory_iterator(dir)) {
        if (!e.is_regular_file()) continue;
        try {
            const MapFileHeader h = readMapHeader(e.path().string());
            if (parseVariant(h.variant)) found.push_back({h.variant, e.path().string()});
        } catch (const std::exception&) {
            // not a map file
        }
    }
    return found;
}

double seconds(std::chrono::steady_clock::time_point since) {
    return std::round(std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count() * 100.0) / 100.0;
}

// Paper order: fls_only, carve_only, paper, fused.
int variantRank(const std::string& v) {
    const auto parsed = parseVariant(v);
    return parsed ? static_cast<int>(*parsed) : 99;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"sf-eval: score sonarfusion maps against the scenario's ground-truth meshes"};
    std::string scenario_path, json_path, figures_dir, maps_dir, config_path, log_path, survey_dir;
    std::vector<std::string> map_args;
    bool merge = false, no_ply = false;
    VisibilityOptions vis;
    EndFaceSelection face;
    app.add_option("--scenario", scenario_path, "scenario YAML (meshes, trajectory, sensors)")->required()->check(CLI::ExistingFile);
    app.add_option("--map", map_args, "map file, or VARIANT=PATH (repeatable; variant defaults to the file's)");
    app.add_option("--config", config_path,
                   "the sf-mapper YAML the maps were made with: segment them with its settings (default: built-in defaults)")
        ->check(CLI::ExistingFile);
#ifdef SF_EVAL_NAV_LOG
    app.add_option("--log", log_path,
                   "the run's LCM log: report how far NAV was from NAV_TRUTH (channels from the scenario)")
        ->check(CLI::ExistingFile);
#endif
    app.add_option("--maps-dir", maps_dir, "score every map file in this folder")->check(CLI::ExistingDirectory);
    app.add_option("--map-dir", survey_dir,
                   "survey: score the finalised maps of sf-mapper --map-dir (map_<k>.map, map_<k>.objects.json)")
        ->check(CLI::ExistingDirectory);
    app.add_option("--json", json_path, "write report.json here");
    app.add_flag("--merge", merge, "keep the other variants (and extra keys) of an existing --json file");
    app.add_option("--figures", figures_dir, "write PNG projections and PLY clouds here");
    app.add_flag("--no-ply", no_ply, "figures only, no PLY point clouds");
    app.add_option("--sample-spacing", vis.sample_spacing, "m between visibility samples on the object surface")
        ->capture_default_str();
    app.add_option("--threads", vis.threads, "threads for the visibility pass (same result for any count)")
        ->capture_default_str()
        ->check(CLI::Range(1, 64));
    app.add_option("--face-window", face.outward_window, "m in front of a true end face searched for its voxels")
        ->capture_default_str();
    CLI11_PARSE(app, argc, argv);

    try {
        std::vector<MapInput> inputs;
        for (const auto& a : map_args) inputs.push_back(parseMapArgument(a));
        if (!maps_dir.empty())
            for (const auto& m : mapsInDir(maps_dir)) inputs.push_back(m);
        if (inputs.empty() && survey_dir.empty()) throw std::runtime_error("no map given (--map, --maps-dir or --map-dir)");
        if (!inputs.empty() && !survey_dir.empty())
            throw std::runtime_error("--map-dir (a survey) does not mix with --map or --maps-dir");

        MapperConfig base_config;  // what sf-mapper uses without a config file
        if (!config_path.empty()) base_config = loadDaemonConfig(config_path).mapper;
        const EvalScenario scenario = loadEvalScenario(scenario_path);
        NavigationReport navigation;
#ifdef SF_EVAL_NAV_LOG
        if (!log_path.empty()) {
            navigation.asked = true;
            const NavLog log = readNavLog(log_path, scenario.nav_channel, scenario.truth_channel,
                                          scenario.max_message_bytes);
            if (log.lost_data) std::cerr << "sf-eval: warning: " << log_path << " is damaged (bytes skipped)\n";
            if (log.undecodable > 0)
                std::cerr << "sf-eval: warning: " << log.undecodable << " undecodable NAV/NAV_TRUTH events in "
                          << log_path << "\n";
            if (log.nav.empty()) std::cerr << "sf-eval: warning: no " << scenario.nav_channel << " in " << log_path << "\n";
            navigation.stats = compareNavigation(log.nav, log.truth);
        }
#endif
        if (scenario.object_meshes.empty())
            std::cerr << "sf-eval: " << scenario.name << " has no object mesh: every predicted object is false\n";
        if (!survey_dir.empty()) {  // survey scoring (survey.hpp, docs/evaluation.md "Survey scoring")
            std::vector<SurveyMap> maps = readSurveyDir(survey_dir);
            if (maps.empty()) std::cerr << "sf-eval: warning: no map_<k>.map in " << survey_dir << "\n";
            for (SurveyMap& m : maps)
                if (m.objects_source == "segmented") {
                    std::cerr << "sf-eval: " << m.map_path << " has no objects file: segmenting it\n";
                    segmentSurveyMap(m, base_config, scenario.track_axis);
                }
            const auto t0 = std::chrono::steady_clock::now();
            const SurveyTruth truth =
                makeSurveyTruth(scenario.object_meshes, scenario.seabed_meshes, scenario.runs, vis);
            std::cerr << "sf-eval: " << truth.objects.size() << " true object(s), visibility " << seconds(t0) << " s\n";
            const auto t1 = std::chrono::steady_clock::now();
            truthInMaps(truth, maps);
            const SurveyScore score = scoreSurvey(truth, maps);
            std::cerr << "sf-eval: " << maps.size() << " map(s) voxelised and matched, " << seconds(t1) << " s\n";
            std::cout << "scenario " << scenario.name << " (survey, " << maps.size() << " map(s))\n" << surveyTable(score);
            if (navigation.asked) std::cout << navigationSummary(navigation) << "\n";
            if (!json_path.empty()) {
                writeSurveyReport(json_path, scenario.name, score, maps, navigation);
                std::cerr << "sf-eval: wrote " << json_path << "\n";
            }
            if (!figures_dir.empty()) {
                for (const auto& p : writeSurveyFigures(figures_dir, scenario.name, truth, scenario.seabed_meshes, maps,
                                                        base_config.segmentation.occupied_probability))
                    std::cerr << "sf-eval: wrote " << p << "\n";
                if (!no_ply)
                    for (const auto& p : writeSurveyPointClouds(figures_dir, maps, score))
                        std::cerr << "sf-eval: wrote " << p << "\n";
            }
            return 0;
        }
        std::cerr << "sf-eval: ground truth and visibility for " << scenario.name << " ...\n";
        const auto t0 = std::chrono::steady_clock::now();
        const SceneTruth scene = makeSceneTruth(scenario.name, scenario.object_meshes, scenario.seabed_meshes,
                                                scenario.runs, scenario.along_track, vis);
        std::cerr << "sf-eval: " << scene.samples.size() << " surface samples, " << scene.objects_true
                  << " true object(s), " << seconds(t0) << " s\n";
        SceneTruth scored_scene = scene;
        scored_scene.declared_face_angle_deg = scenario.declared_face_angle_deg;

        struct Loaded {
            std::string variant, path;
            std::unique_ptr<VoxelMap> map;
            Prediction prediction;
            std::shared_ptr<GroundTruth> truth;
            VariantScore score;
        };
        std::vector<Loaded> loaded;
        std::vector<std::shared_ptr<GroundTruth>> truths;  // one per distinct grid
        for (const MapInput& in : inputs) {
            const MapFileHeader h = readMapHeader(in.path);
            const std::string name = in.variant.empty() ? h.variant : in.variant;
            const auto variant = parseVariant(name);
            if (!variant) throw std::runtime_error(in.path + ": unknown variant '" + name + "' (give VARIANT=PATH)");
            if (!h.initialised) std::cerr << "sf-eval: warning: " << in.path << " was never initialised (empty map)\n";
            Loaded l{name, in.path, std::make_unique<VoxelMap>(mapConfigOf(h)), {}, nullptr, {}};
            loadMap(in.path, *l.map);
            const GridSpec grid = GridSpec::of(*l.map);
            for (const auto& t : truths)
                if (t->grid == grid) l.truth = t;
            if (!l.truth) {
                const auto t1 = std::chrono::steady_clock::now();
                l.truth = std::make_shared<GroundTruth>(groundTruthInGrid(scene, grid));
                truths.push_back(l.truth);
                std::cerr << "sf-eval: ground-truth voxels in the grid of " << in.path << ", " << seconds(t1) << " s\n";
            }
            l.prediction = segmentMap(*l.map, *variant, base_config, scenario.track_axis);
            l.score = scorePrediction(grid, l.prediction, *l.truth, scored_scene, face);
            l.score.missed = missedVisible(grid, *l.map, l.prediction, l.truth->visible);
            l.score.variant = name;
            l.score.map_path = in.path;
            loaded.push_back(std::move(l));
        }
        std::stable_sort(loaded.begin(), loaded.end(),
                         [](const Loaded& a, const Loaded& b) { return variantRank(a.variant) < variantRank(b.variant); });

        std::vector<VariantScore> scores;
        for (const auto& l : loaded) scores.push_back(l.score);
        std::cout << "scenario " << scenario.name << "\n" << scoreTable(scores);
        if (navigation.asked) std::cout << navigationSummary(navigation) << "\n";
        if (!json_path.empty()) {
            writeReport(json_path, scenario.name, scores, merge, navigation);
            std::cerr << "sf-eval: wrote " << json_path << "\n";
        }
        if (!figures_dir.empty()) {
            std::vector<FigurePanel> panels;
            for (const auto& l : loaded) panels.push_back({l.variant, l.map.get(), &l.prediction, l.truth.get()});
            for (const auto& p : writeFigures(figures_dir, scenario.name, scene, panels)) std::cerr << "sf-eval: wrote " << p << "\n";
            if (!no_ply)
                for (std::size_t k = 0; k < panels.size(); ++k)
                    for (const auto& p : writePointClouds(figures_dir, panels[k], k == 0))
                        std::cerr << "sf-eval: wrote " << p << "\n";
        }
    } catch (const std::exception& e) {
        std::cerr << "sf-eval: " << e.what() << "\n";
        return 1;
    }
    return 0;
}
