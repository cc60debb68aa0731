#include "scenario.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "sonarfusion/fls_model.hpp"
#include "sonarfusion/ps_model.hpp"

namespace sonarfusion::sim {

namespace {

namespace fs = std::filesystem;

// A YAML mapping read key by key: remembers which keys were used so that a
// misspelt key is reported instead of silently ignored.
class Fields {
public:
    Fields(const YAML::Node& node, std::string path) : node_(node), path_(std::move(path)) {
        if (node_ && !node_.IsNull() && !node_.IsMap()) throw ScenarioError(path_, "must be a mapping");
    }

    [[nodiscard]] std::string field(const std::string& key) const {
        return path_.empty() ? key : path_ + "." + key;
    }
    [[nodiscard]] bool has(const std::string& key) const { return node_ && node_.IsMap() && node_[key]; }

    YAML::Node child(const std::string& key) {
        used_.insert(key);
        return has(key) ? node_[key] : YAML::Node();
    }

    template <class T>
    T get(const std::string& key, T fallback) {
        const YAML::Node n = child(key);
        if (!n.IsDefined() || n.IsNull()) return fallback;
        try {
            return n.as<T>();
        } catch (const YAML::Exception&) {
            throw ScenarioError(field(key), "cannot read '" + scalarText(n) + "' as a " + typeName<T>());
        }
    }

    template <class T>
    T require(const std::string& key) {
        if (!has(key)) throw ScenarioError(field(key), "is required");
        return get<T>(key, T{});
    }

    // Angles are written in degrees in the file and kept in radians.
    double degrees(const std::string& key, double fallback_rad) {
        return get<double>(key, fallback_rad / kDegToRad) * kDegToRad;
    }

    void rejectUnknownKeys() const {
        if (!node_ || !node_.IsMap()) return;
        for (const auto& kv : node_) {
            const std::string key = kv.first.as<std::string>();
            if (!used_.count(key)) throw ScenarioError(field(key), "unknown key");
        }
    }

private:
    static std::string scalarText(const YAML::Node& n) {
        if (n.IsScalar()) return n.Scalar();
        std::ostringstream os;
        os << n;
        return os.str();
    }
    template <class T>
    static const char* typeName() {
        if constexpr (std::is_same_v<T, bool>) return "boolean";
        if constexpr (std::is_integral_v<T>) return "integer";
        if constexpr (std::is_floating_point_v<T>) return "number";
        return "string";
    }

    YAML::Node node_;
    std::string path_;
    std::set<std::string> used_;
};

void check(bool ok, const std::string& field, const std::string& problem) {
    if (!ok) throw ScenarioError(field, problem);
}

Mounting readMounting(const YAML::Node& node, const std::string& path) {
    Fields f(node, path);
    Mounting m;
    m.x = f.get("x", m.x);
    m.y = f.get("y", m.y);
    m.z = f.get("z", m.z);
    m.roll = f.degrees("roll_deg", m.roll);
    m.yaw = f.degrees("yaw_deg", m.yaw);
    f.rejectUnknownKeys();
    return m;
}

std::vector<double> readList(Fields& f, const std::string& key, double scale) {
    std::vector<double> out;
    for (double v : f.get<std::vector<double>>(key, {})) out.push_back(v * scale);
    return out;
}

void readFls(const YAML::Node& node, Scenario& s) {
    Fields f(node, "fls");
    FlsGeometry& g = s.fls;
    FlsSimParams& p = s.fls_sim;
    p.name = f.get("name", p.name);
    g.fov_horizontal = f.degrees("fov_horizontal_deg", g.fov_horizontal);
    g.elevation_min = f.degrees("elevation_min_deg", g.elevation_min);
    g.elevation_max = f.degrees("elevation_max_deg", g.elevation_max);
    g.tilt = f.degrees("tilt_deg", g.tilt);
    g.range_min = f.get("range_min", g.range_min);
    g.range_max = f.get("range_max", g.range_max);
    g.beams = f.get("beams", g.beams);
    g.rows = f.get("rows", g.rows);
    g.elevation_samples = f.get("elevation_samples", g.elevation_samples);
    g.beam_bearing = readList(f, "beam_bearing_deg", kDegToRad);
    g.row_range = readList(f, "row_range", 1.0);
    p.rays_azimuth = f.get("rays_azimuth", p.rays_azimuth);
    p.rays_elevation = f.get("rays_elevation", p.rays_elevation);
    p.gain_db = f.get("gain_db", p.gain_db);
    p.tvg_db_per_decade = f.get("tvg_db_per_decade", p.tvg_db_per_decade);
    p.source_level = f.get("source_level", p.source_level);
    p.sound_speed = f.get("sound_speed", p.sound_speed);
    p.frequency_hz = f.get("frequency_hz", p.frequency_hz);
    s.fls_mount = readMounting(f.child("mount"), "fls.mount");
    f.rejectUnknownKeys();

    check(g.range_min >= 0.0, "fls.range_min", "must be >= 0");
    check(g.range_max > g.range_min, "fls.range_max", "must be > range_min");
    check(g.fov_horizontal > 0.0, "fls.fov_horizontal_deg", "must be > 0");
    check(g.elevation_max >= g.elevation_min, "fls.elevation_max_deg", "must be >= elevation_min_deg");
    check(g.beams >= 1 && g.beams <= 4096, "fls.beams", "must be in 1..4096");
    check(g.rows >= 2 && g.rows <= 16384, "fls.rows", "must be in 2..16384");
    check(g.elevation_samples >= 1, "fls.elevation_samples", "must be >= 1");
    check(g.beam_bearing.empty() || static_cast<int>(g.beam_bearing.size()) == g.beams, "fls.beam_bearing_deg",
          "must have one entry per beam");
    check(g.row_range.empty() || static_cast<int>(g.row_range.size()) == g.rows, "fls.row_range",
          "must have one entry per row");
    check(p.rays_azimuth >= 1 && p.rays_azimuth <= 64, "fls.rays_azimuth", "must be in 1..64");
    check(p.rays_elevation >= 1 && p.rays_elevation <= 8192, "fls.rays_elevation", "must be in 1..8192");
    check(p.source_level > 0.0, "fls.source_level", "must be > 0");
    try {
        (void)FlsModel(g);
    } catch (const std::invalid_argument& e) {
        throw ScenarioError("fls", e.what());
    }
}

void readPs(const YAML::Node& node, Scenario& s) {
    Fields f(node, "ps");
    PsGeometry& g = s.ps;
    PsSimParams& p = s.ps_sim;
    p.name = f.get("name", p.name);
    g.fan_min = f.degrees("fan_min_deg", g.fan_min);
    g.fan_max = f.degrees("fan_max_deg", g.fan_max);
    g.head_min = f.degrees("head_min_deg", g.head_min);
    g.head_max = f.degrees("head_max_deg", g.head_max);
    g.tilt = f.degrees("tilt_deg", g.tilt);
    g.range_min = f.get("range_min", g.range_min);
    g.range_max = f.get("range_max", g.range_max);
    g.bins = f.get("bins", g.bins);
    g.fan_samples = f.get("fan_samples", g.fan_samples);
    p.head_step = f.degrees("head_step_deg", p.head_step);
    p.beam_width_vertical = f.degrees("beam_width_vertical_deg", p.beam_width_vertical);
    p.rays_fan = f.get("rays_fan", p.rays_fan);
    p.rays_vertical = f.get("rays_vertical", p.rays_vertical);
    p.gain_db = f.get("gain_db", p.gain_db);
    p.tvg_db_per_decade = f.get("tvg_db_per_decade", p.tvg_db_per_decade);
    p.source_level = f.get("source_level", p.source_level);
    s.ps_mount = readMounting(f.child("mount"), "ps.mount");
    f.rejectUnknownKeys();

    check(g.range_min >= 0.0, "ps.range_min", "must be >= 0");
    check(g.range_max > g.range_min, "ps.range_max", "must be > range_min");
    check(g.fan_max >= g.fan_min, "ps.fan_max_deg", "must be >= fan_min_deg");
    check(g.head_max >= g.head_min, "ps.head_max_deg", "must be >= head_min_deg");
    check(g.bins >= 2 && g.bins <= 65536, "ps.bins", "must be in 2..65536");
    check(g.fan_samples >= 1, "ps.fan_samples", "must be >= 1");
    check(p.head_step > 0.0, "ps.head_step_deg", "must be > 0");
    check(p.beam_width_vertical >= 0.0, "ps.beam_width_vertical_deg", "must be >= 0");
    check(p.rays_fan >= 1 && p.rays_fan <= 8192, "ps.rays_fan", "must be in 1..8192");
    check(p.rays_vertical >= 1 && p.rays_vertical <= 256, "ps.rays_vertical", "must be in 1..256");
    check(p.source_level > 0.0, "ps.source_level", "must be > 0");
    try {
        (void)PsModel(g);
    } catch (const std::invalid_argument& e) {
        throw ScenarioError("ps", e.what());
    }
}

void readScene(const YAML::Node& node, const fs::path& base_dir, Scenario& s) {
    Fields f(node, "scene");
    s.scene.water_impedance = f.get("water_impedance", s.scene.water_impedance);
    s.scene.seabed_depth = f.get("seabed_depth", s.scene.seabed_depth);
    const YAML::Node meshes = f.child("meshes");
    f.rejectUnknownKeys();
    check(s.scene.water_impedance > 0.0, "scene.water_impedance", "must be > 0");
    check(meshes && meshes.IsSequence() && meshes.size() > 0, "scene.meshes", "needs at least one mesh");
    for (std::size_t i = 0; i < meshes.size(); ++i) {
        const std::string path = "scene.meshes[" + std::to_string(i) + "]";
        Fields m(meshes[i], path);
        MeshSpec spec;
        const std::string file = m.require<std::string>("file");
        const std::string role = m.require<std::string>("role");
        spec.impedance = m.get("impedance", role == "seabed" ? 3.0 : 8.0);
        spec.face_angle_deg = m.get("face_angle_deg", 0.0);
        m.rejectUnknownKeys();
        if (role == "seabed") spec.role = MeshRole::Seabed;
        else if (role == "object") spec.role = MeshRole::Object;
        else throw ScenarioError(path + ".role", "must be 'seabed' or 'object', not '" + role + "'");
        check(spec.impedance > 0.0, path + ".impedance", "must be > 0");
        const fs::path resolved = fs::path(file).is_absolute() ? fs::path(file) : base_dir / file;
        check(fs::is_regular_file(resolved), path + ".file", "no such mesh file: " + resolved.string());
        spec.path = resolved.lexically_normal().string();
        s.scene.meshes.push_back(spec);
    }
}

void readNoise(const YAML::Node& node, Scenario& s) {
    Fields f(node, "noise");
    NoiseSpec& n = s.noise;
    n.speckle = f.get("speckle", n.speckle);
    n.scatterers = f.get("scatterers", n.scatterers);
    n.coherent_fraction = f.get("coherent_fraction", n.coherent_fraction);
    n.floor = f.get("floor", n.floor);
    n.follows_pose = f.get("follows_pose", n.follows_pose);
    f.rejectUnknownKeys();
    check(n.scatterers >= 1 && n.scatterers <= 1024, "noise.scatterers", "must be in 1..1024");
    check(n.coherent_fraction >= 0.0 && n.coherent_fraction <= 1.0, "noise.coherent_fraction", "must be in 0..1");
    check(n.floor >= 0.0, "noise.floor", "must be >= 0");
}

// A number that must be finite and >= 0 (NaN and inf refused by name).
void checkNonNegative(double v, const std::string& field) {
    check(std::isfinite(v), field, "must be a finite number");
    check(v >= 0.0, field, "must be >= 0");
}

void readNavigation(const YAML::Node& node, Scenario& s) {
    Fields f(node, "navigation");
    NavigationSpec& n = s.navigation;
    n.position_noise = f.get("position_noise", n.position_noise);
    n.depth_noise = f.get("depth_noise", n.depth_noise);
    n.drift_fraction = f.get("drift_fraction", n.drift_fraction);
    n.heading_bias = f.degrees("heading_bias_deg", n.heading_bias);
    n.heading_noise = f.degrees("heading_noise_deg", n.heading_noise);
    n.attitude_noise = f.degrees("attitude_noise_deg", n.attitude_noise);
    n.latency = f.get("latency", n.latency);
    f.rejectUnknownKeys();
    checkNonNegative(n.position_noise, "navigation.position_noise");
    checkNonNegative(n.depth_noise, "navigation.depth_noise");
    checkNonNegative(n.drift_fraction, "navigation.drift_fraction");
    check(std::isfinite(n.heading_bias), "navigation.heading_bias_deg", "must be a finite number");
    checkNonNegative(n.heading_noise, "navigation.heading_noise_deg");
    checkNonNegative(n.attitude_noise, "navigation.attitude_noise_deg");
    checkNonNegative(n.latency, "navigation.latency");
}

void readMotion(const YAML::Node& node, Scenario& s) {
    Fields f(node, "motion");
    MotionSpec& m = s.motion;
    m.roll_amplitude = f.degrees("roll_amplitude_deg", m.roll_amplitude);
    m.pitch_amplitude = f.degrees("pitch_amplitude_deg", m.pitch_amplitude);
    m.yaw_amplitude = f.degrees("yaw_amplitude_deg", m.yaw_amplitude);
    m.heave_amplitude = f.get("heave_amplitude", m.heave_amplitude);
    m.period = f.get("period", m.period);
    f.rejectUnknownKeys();
    checkNonNegative(m.roll_amplitude, "motion.roll_amplitude_deg");
    checkNonNegative(m.pitch_amplitude, "motion.pitch_amplitude_deg");
    checkNonNegative(m.yaw_amplitude, "motion.yaw_amplitude_deg");
    checkNonNegative(m.heave_amplitude, "motion.heave_amplitude");
    checkNonNegative(m.period, "motion.period");
    check(!m.enabled() || m.period > 0.0, "motion.period", "must be > 0 when an amplitude is not 0");
}

void readTrajectory(const YAML::Node& node, Scenario& s) {
    Fields f(node, "trajectory");
    TrajectorySpec& t = s.trajectory;
    t.sequence_period = f.get("sequence_period", t.sequence_period);
    t.start_utime = f.get("start_utime", t.start_utime);
    t.pass_gap = f.get("pass_gap", t.pass_gap);
    t.fls_every = f.get("fls_every", t.fls_every);
    const YAML::Node passes = f.child("passes");
    const YAML::Node waypoints = f.child("waypoints");
    f.rejectUnknownKeys();
    check(t.sequence_period > 0.0, "trajectory.sequence_period", "must be > 0");
    check(t.start_utime >= 0, "trajectory.start_utime", "must be >= 0");
    check(t.pass_gap >= 0.0, "trajectory.pass_gap", "must be >= 0");
    check(t.fls_every >= 1, "trajectory.fls_every", "must be >= 1");
    check(passes.IsNull() || passes.IsSequence(), "trajectory.passes", "must be a list");
    check(waypoints.IsNull() || waypoints.IsSequence(), "trajectory.waypoints", "must be a list");

    for (std::size_t i = 0; passes.IsSequence() && i < passes.size(); ++i) {
        const std::string path = "trajectory.passes[" + std::to_string(i) + "]";
        Fields p(passes[i], path);
        StraightPass pass;
        pass.heading = p.degrees("heading_deg", pass.heading);
        pass.altitude = p.get("altitude", pass.altitude);
        pass.step = p.get("step", pass.step);
        pass.sequences = p.require<int>("sequences");
        pass.start_offset = p.get("start_offset", pass.start_offset);
        const auto centre = p.get<std::vector<double>>("centre", {0.0, 0.0});
        p.rejectUnknownKeys();
        check(centre.size() == 2, path + ".centre", "must be [x, y]");
        pass.centre_x = centre[0];
        pass.centre_y = centre[1];
        check(pass.sequences >= 1, path + ".sequences", "must be >= 1");
        check(pass.step >= 0.0, path + ".step", "must be >= 0");
        check(pass.altitude > 0.0, path + ".altitude", "must be > 0");
        t.passes.push_back(pass);
    }
    for (std::size_t i = 0; waypoints.IsSequence() && i < waypoints.size(); ++i) {
        const std::string path = "trajectory.waypoints[" + std::to_string(i) + "]";
        Fields w(waypoints[i], path);
        WaypointPath wp;
        wp.step = w.get("step", wp.step);
        const auto points = w.get<std::vector<std::vector<double>>>("points", {});
        w.rejectUnknownKeys();
        check(wp.step > 0.0, path + ".step", "must be > 0");
        check(points.size() >= 2, path + ".points", "needs at least two [x, y, z] points");
        for (const auto& pt : points) {
            check(pt.size() == 3, path + ".points", "each point must be [x, y, z]");
            wp.points.push_back({pt[0], pt[1], pt[2]});
        }
        t.waypoints.push_back(wp);
    }
    check(!t.passes.empty() || !t.waypoints.empty(), "trajectory",
          "is empty: give at least one entry in 'passes' or 'waypoints'");
}

Scenario parse(const YAML::Node& root, const fs::path& base_dir) {
    Fields top(root, "");
    Scenario s;
    s.name = top.get<std::string>("name", "");
    s.seed = top.get<uint64_t>("seed", s.seed);
    if (!top.has("scene")) throw ScenarioError("scene", "is required");
    if (!top.has("trajectory")) throw ScenarioError("trajectory", "is required");
    readScene(top.child("scene"), base_dir, s);
    readFls(top.child("fls"), s);
    readPs(top.child("ps"), s);
    readNoise(top.child("noise"), s);
    readNavigation(top.child("navigation"), s);
    readMotion(top.child("motion"), s);
    readTrajectory(top.child("trajectory"), s);
    Fields ch(top.child("channels"), "channels");
    s.channels.nav = ch.get("nav", s.channels.nav);
    s.channels.fls = ch.get("fls", s.channels.fls);
    s.channels.ps = ch.get("ps", s.channels.ps);
    s.channels.nav_truth = ch.get("nav_truth", s.channels.nav_truth);
    ch.rejectUnknownKeys();
    check(!s.channels.nav.empty() && !s.channels.fls.empty() && !s.channels.ps.empty(), "channels",
          "channel names must not be empty");
    check(!s.channels.nav_truth.empty(), "channels.nav_truth", "must not be empty");
    check(!s.publishesTruth() || (s.channels.nav_truth != s.channels.nav && s.channels.nav_truth != s.channels.fls &&
                                  s.channels.nav_truth != s.channels.ps),
          "channels.nav_truth", "must differ from the nav, fls and ps channels");
    top.rejectUnknownKeys();
    return s;
}

}  // namespace

double Scenario::trueFaceAngleDeg() const {
    for (const auto& m : scene.meshes)
        if (m.role == MeshRole::Object && m.face_angle_deg > 0.0) return m.face_angle_deg;
    return 0.0;
}

std::vector<std::string> Scenario::meshPaths(MeshRole role) const {
    std::vector<std::string> out;
    for (const auto& m : scene.meshes)
        if (m.role == role) out.push_back(m.path);
    return out;
}

Scenario loadScenarioFromString(const std::string& yaml, const std::string& base_dir) {
    YAML::Node root;
    try {
        root = YAML::Load(yaml);
    } catch (const YAML::Exception& e) {
        throw ScenarioError("(file)", std::string("YAML syntax error: ") + e.what());
    }
    if (!root.IsMap()) throw ScenarioError("(file)", "top level must be a mapping");
    return parse(root, fs::path(base_dir));
}

Scenario loadScenario(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw ScenarioError("--scenario", "cannot open " + path);
    std::stringstream text;
    text << in.rdbuf();
    Scenario s = loadScenarioFromString(text.str(), fs::absolute(fs::path(path)).parent_path().string());
    s.source_path = path;
    return s;
}

}  // namespace sonarfusion::sim
