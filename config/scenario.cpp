#include "scenario.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "config_yaml.hpp"
#include "sonarfusion/pose.hpp"

namespace sonarfusion::sim {

namespace {

namespace fs = std::filesystem;
using config_yaml::Fields;
using config_yaml::requireValid;
using Check = std::optional<ConfigIssue>;

Check bad(const std::string& key, const std::string& reason) { return ConfigIssue{key, reason}; }
// A number that must be finite and >= 0 (NaN and inf refused by name).
Check nonNegative(double v, const char* key) {
    if (!std::isfinite(v)) return bad(key, "must be a finite number");
    if (v < 0.0) return bad(key, "must be >= 0");
    return std::nullopt;
}

void readFls(const YAML::Node& node, Scenario& s) {
    Fields f(node, "fls");
    FlsSimParams& p = s.fls_sim;
    f.read("name", p.name);
    config_yaml::readFlsGeometry(f, s.fls);
    f.read("rays_azimuth", p.rays_azimuth);
    f.read("rays_elevation", p.rays_elevation);
    f.read("gain_db", p.gain_db);
    f.read("tvg_db_per_decade", p.tvg_db_per_decade);
    f.read("source_level", p.source_level);
    f.read("sound_speed", p.sound_speed);
    f.read("frequency_hz", p.frequency_hz);
    const YAML::Node windows = f.child("window_changes");
    if (!(windows.IsNull() || !windows.IsDefined() || windows.IsSequence()))
        throw config_yaml::KeyError("fls.window_changes", "must be a list");
    for (std::size_t i = 0; windows.IsSequence() && i < windows.size(); ++i) {
        const std::string path = "fls.window_changes[" + std::to_string(i) + "]";
        Fields w(windows[i], path);
        FlsWindowChange c;
        c.at_sequence = w.require<int64_t>("at_sequence");
        c.range_min = w.require<double>("range_min");
        c.range_max = w.require<double>("range_max");
        w.rejectUnknownKeys();
        requireValid(c, path);
        p.window_changes.push_back(c);
    }
    config_yaml::readMounting(f.child("mount"), "fls.mount", s.fls_mount);
    f.rejectUnknownKeys();
    requireValid(s.fls, "fls");
    requireValid(p, "fls");
}

void readPs(const YAML::Node& node, Scenario& s) {
    Fields f(node, "ps");
    PsSimParams& p = s.ps_sim;
    f.read("name", p.name);
    config_yaml::readPsGeometry(f, s.ps);
    f.readDegrees("head_step_deg", p.head_step);
    f.readDegrees("beam_width_vertical_deg", p.beam_width_vertical);
    f.read("rays_fan", p.rays_fan);
    f.read("rays_vertical", p.rays_vertical);
    f.read("gain_db", p.gain_db);
    f.read("tvg_db_per_decade", p.tvg_db_per_decade);
    f.read("source_level", p.source_level);
    config_yaml::readMounting(f.child("mount"), "ps.mount", s.ps_mount);
    f.rejectUnknownKeys();
    requireValid(s.ps, "ps");
    requireValid(p, "ps");
}

void readScene(const YAML::Node& node, const fs::path& base_dir, Scenario& s) {
    Fields f(node, "scene");
    f.read("water_impedance", s.scene.water_impedance);
    f.read("seabed_depth", s.scene.seabed_depth);
    const YAML::Node meshes = f.child("meshes");
    f.rejectUnknownKeys();
    if (!(meshes && meshes.IsSequence() && meshes.size() > 0))
        throw config_yaml::KeyError("scene.meshes", "needs at least one mesh");
    for (std::size_t i = 0; i < meshes.size(); ++i) {
        const std::string path = "scene.meshes[" + std::to_string(i) + "]";
        Fields m(meshes[i], path);
        MeshSpec spec;
        const std::string file = m.require<std::string>("file");
        const std::string role = m.require<std::string>("role");
        spec.impedance = m.get("impedance", role == "seabed" ? 3.0 : 8.0);
        m.read("face_angle_deg", spec.face_angle_deg);
        m.read("scale", spec.scale);
        const auto triple = [&](const std::string& key, std::array<double, 3>& out, double unit) {
            const auto v = m.get<std::vector<double>>(key, {out[0], out[1], out[2]});
            if (v.size() != 3) throw config_yaml::KeyError(path + "." + key, "must be a list of three numbers");
            for (int k = 0; k < 3; ++k) out[k] = v[k] * unit;
        };
        triple("position", spec.position, 1.0);
        triple("rpy_deg", spec.rotation, kDegToRad);
        m.rejectUnknownKeys();
        if (role == "seabed")
            spec.role = MeshRole::Seabed;
        else if (role == "object")
            spec.role = MeshRole::Object;
        else
            throw config_yaml::KeyError(path + ".role", "must be 'seabed' or 'object', not '" + role + "'");
        requireValid(spec, path);
        const fs::path resolved = fs::path(file).is_absolute() ? fs::path(file) : base_dir / file;
        if (!fs::is_regular_file(resolved))
            throw config_yaml::KeyError(path + ".file", "no such mesh file: " + resolved.string());
        spec.path = resolved.lexically_normal().string();
        s.scene.meshes.push_back(spec);
    }
    requireValid(s.scene, "scene");
}

void readNoise(const YAML::Node& node, Scenario& s) {
    Fields f(node, "noise");
    NoiseSpec& n = s.noise;
    f.read("speckle", n.speckle);
    f.read("scatterers", n.scatterers);
    f.read("coherent_fraction", n.coherent_fraction);
    f.read("floor", n.floor);
    f.read("follows_pose", n.follows_pose);
    f.rejectUnknownKeys();
    requireValid(n, "noise");
}

void readNavigation(const YAML::Node& node, Scenario& s) {
    Fields f(node, "navigation");
    NavigationSpec& n = s.navigation;
    f.read("position_noise", n.position_noise);
    f.read("depth_noise", n.depth_noise);
    f.read("drift_fraction", n.drift_fraction);
    f.readDegrees("heading_bias_deg", n.heading_bias);
    f.readDegrees("heading_noise_deg", n.heading_noise);
    f.readDegrees("attitude_noise_deg", n.attitude_noise);
    f.read("latency", n.latency);
    f.rejectUnknownKeys();
    requireValid(n, "navigation");
}

void readMotion(const YAML::Node& node, Scenario& s) {
    Fields f(node, "motion");
    MotionSpec& m = s.motion;
    f.readDegrees("roll_amplitude_deg", m.roll_amplitude);
    f.readDegrees("pitch_amplitude_deg", m.pitch_amplitude);
    f.readDegrees("yaw_amplitude_deg", m.yaw_amplitude);
    f.read("heave_amplitude", m.heave_amplitude);
    f.read("period", m.period);
    f.rejectUnknownKeys();
    requireValid(m, "motion");
}

void readTrajectory(const YAML::Node& node, Scenario& s) {
    Fields f(node, "trajectory");
    TrajectorySpec& t = s.trajectory;
    f.read("sequence_period", t.sequence_period);
    f.read("start_utime", t.start_utime);
    f.read("pass_gap", t.pass_gap);
    f.read("fls_every", t.fls_every);
    const YAML::Node passes = f.child("passes");
    const YAML::Node waypoints = f.child("waypoints");
    f.rejectUnknownKeys();
    if (!(passes.IsNull() || passes.IsSequence())) throw config_yaml::KeyError("trajectory.passes", "must be a list");
    if (!(waypoints.IsNull() || waypoints.IsSequence()))
        throw config_yaml::KeyError("trajectory.waypoints", "must be a list");

    for (std::size_t i = 0; passes.IsSequence() && i < passes.size(); ++i) {
        const std::string path = "trajectory.passes[" + std::to_string(i) + "]";
        Fields p(passes[i], path);
        StraightPass pass;
        p.readDegrees("heading_deg", pass.heading);
        p.read("altitude", pass.altitude);
        p.read("step", pass.step);
        pass.sequences = p.require<int>("sequences");
        p.read("start_offset", pass.start_offset);
        const auto centre = p.get<std::vector<double>>("centre", {0.0, 0.0});
        p.rejectUnknownKeys();
        if (centre.size() != 2) throw config_yaml::KeyError(path + ".centre", "must be [x, y]");
        pass.centre_x = centre[0];
        pass.centre_y = centre[1];
        requireValid(pass, path);
        t.passes.push_back(pass);
    }
    for (std::size_t i = 0; waypoints.IsSequence() && i < waypoints.size(); ++i) {
        const std::string path = "trajectory.waypoints[" + std::to_string(i) + "]";
        Fields w(waypoints[i], path);
        WaypointPath wp;
        w.read("step", wp.step);
        const auto points = w.get<std::vector<std::vector<double>>>("points", {});
        w.rejectUnknownKeys();
        for (const auto& pt : points) {
            if (pt.size() != 3) throw config_yaml::KeyError(path + ".points", "each point must be [x, y, z]");
            wp.points.push_back({pt[0], pt[1], pt[2]});
        }
        requireValid(wp, path);
        t.waypoints.push_back(wp);
    }
    requireValid(t, "trajectory");
}

Scenario parse(const YAML::Node& root, const fs::path& base_dir) {
    Fields top(root, "");
    Scenario s;
    s.name = top.get<std::string>("name", "");
    top.read("seed", s.seed);
    if (!top.has("scene")) throw config_yaml::KeyError("scene", "is required");
    if (!top.has("trajectory")) throw config_yaml::KeyError("trajectory", "is required");
    readScene(top.child("scene"), base_dir, s);
    readFls(top.child("fls"), s);
    readPs(top.child("ps"), s);
    readNoise(top.child("noise"), s);
    readNavigation(top.child("navigation"), s);
    readMotion(top.child("motion"), s);
    readTrajectory(top.child("trajectory"), s);
    Fields ch(top.child("channels"), "channels");
    ch.read("nav", s.channels.nav);
    ch.read("fls", s.channels.fls);
    ch.read("ps", s.channels.ps);
    ch.read("nav_truth", s.channels.nav_truth);
    ch.rejectUnknownKeys();
    top.rejectUnknownKeys();
    requireValid(s, "");  // every block again (cheap), and the rules across blocks
    return s;
}

// Any key error of the shared reader, as the scenario's error type.
Scenario parseNamingTheField(const YAML::Node& root, const fs::path& base_dir) {
    try {
        return parse(root, base_dir);
    } catch (const config_yaml::KeyError& e) {
        throw ScenarioError(e.key(), e.problem());
    }
}

}  // namespace

Check MeshSpec::validate() const {
    if (!(impedance > 0.0) || !std::isfinite(impedance)) return bad("impedance", "must be > 0");
    if (!std::isfinite(face_angle_deg)) return bad("face_angle_deg", "must be a finite number");
    // Zero or negative would collapse or mirror the mesh (turning its normals inward).
    if (!(scale > 0.0) || !std::isfinite(scale)) return bad("scale", "must be a number > 0");
    for (double v : position)
        if (!std::isfinite(v)) return bad("position", "must be three finite numbers");
    for (double v : rotation)
        if (!std::isfinite(v)) return bad("rpy_deg", "must be three finite numbers");
    return std::nullopt;
}

Eigen::Isometry3d MeshSpec::pose() const {
    Pose p;
    p.position = Eigen::Vector3d(position[0], position[1], position[2]);
    p.roll = rotation[0];
    p.pitch = rotation[1];
    p.yaw = rotation[2];
    Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
    out.linear() = p.rotation();
    out.translation() = p.position;
    return out;
}

Check SceneSpec::validate() const {
    if (!(water_impedance > 0.0) || !std::isfinite(water_impedance)) return bad("water_impedance", "must be > 0");
    if (!std::isfinite(seabed_depth)) return bad("seabed_depth", "must be a finite number");
    if (meshes.empty()) return bad("meshes", "needs at least one mesh");
    for (std::size_t i = 0; i < meshes.size(); ++i)
        if (Check c = meshes[i].validate()) return c->in("meshes[" + std::to_string(i) + "]");
    return std::nullopt;
}

Check FlsSimParams::validate() const {
    for (std::size_t i = 0; i < window_changes.size(); ++i) {
        const std::string key = "window_changes[" + std::to_string(i) + "]";
        if (Check c = window_changes[i].validate()) return c->in(key);
        if (i > 0 && window_changes[i].at_sequence <= window_changes[i - 1].at_sequence)
            return bad(key + ".at_sequence", "must be above the previous entry's");
    }
    if (rays_azimuth < 1 || rays_azimuth > 64) return bad("rays_azimuth", "must be in 1..64");
    if (rays_elevation < 1 || rays_elevation > 8192) return bad("rays_elevation", "must be in 1..8192");
    if (!std::isfinite(gain_db)) return bad("gain_db", "must be a finite number");
    if (!std::isfinite(tvg_db_per_decade)) return bad("tvg_db_per_decade", "must be a finite number");
    if (!(source_level > 0.0) || !std::isfinite(source_level)) return bad("source_level", "must be > 0");
    return std::nullopt;
}

Check FlsWindowChange::validate() const {
    if (at_sequence < 1) return bad("at_sequence", "must be >= 1");
    if (!std::isfinite(range_min) || range_min < 0.0) return bad("range_min", "must be finite and >= 0");
    if (!std::isfinite(range_max) || range_max <= range_min || range_max > 1000.0)
        return bad("range_max", "must be above range_min and <= 1000 m");
    return std::nullopt;
}

Check PsSimParams::validate() const {
    if (!(head_step > 0.0) || !std::isfinite(head_step)) return bad("head_step_deg", "must be > 0");
    if (!(beam_width_vertical >= 0.0) || !std::isfinite(beam_width_vertical))
        return bad("beam_width_vertical_deg", "must be >= 0");
    if (rays_fan < 1 || rays_fan > 8192) return bad("rays_fan", "must be in 1..8192");
    if (rays_vertical < 1 || rays_vertical > 256) return bad("rays_vertical", "must be in 1..256");
    if (!std::isfinite(gain_db)) return bad("gain_db", "must be a finite number");
    if (!std::isfinite(tvg_db_per_decade)) return bad("tvg_db_per_decade", "must be a finite number");
    if (!(source_level > 0.0) || !std::isfinite(source_level)) return bad("source_level", "must be > 0");
    return std::nullopt;
}

Check NoiseSpec::validate() const {
    if (scatterers < 1 || scatterers > 1024) return bad("scatterers", "must be in 1..1024");
    if (!(coherent_fraction >= 0.0 && coherent_fraction <= 1.0)) return bad("coherent_fraction", "must be in 0..1");
    if (Check c = nonNegative(floor, "floor")) return c;
    return std::nullopt;
}

Check StraightPass::validate() const {
    if (sequences < 1) return bad("sequences", "must be >= 1");
    if (!(step >= 0.0) || !std::isfinite(step)) return bad("step", "must be >= 0");
    if (!(altitude > 0.0) || !std::isfinite(altitude)) return bad("altitude", "must be > 0");
    if (!std::isfinite(heading)) return bad("heading_deg", "must be a finite number");
    if (!std::isfinite(start_offset)) return bad("start_offset", "must be a finite number");
    if (!std::isfinite(centre_x) || !std::isfinite(centre_y)) return bad("centre", "must be finite");
    return std::nullopt;
}

Check WaypointPath::validate() const {
    if (!(step > 0.0) || !std::isfinite(step)) return bad("step", "must be > 0");
    if (points.size() < 2) return bad("points", "needs at least two [x, y, z] points");
    for (const auto& p : points)
        if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
            return bad("points", "every coordinate must be finite");
    return std::nullopt;
}

Check TrajectorySpec::validate() const {
    if (!(sequence_period > 0.0) || !std::isfinite(sequence_period)) return bad("sequence_period", "must be > 0");
    if (start_utime < 0) return bad("start_utime", "must be >= 0");
    if (Check c = nonNegative(pass_gap, "pass_gap")) return c;
    if (fls_every < 1) return bad("fls_every", "must be >= 1");
    for (std::size_t i = 0; i < passes.size(); ++i)
        if (Check c = passes[i].validate()) return c->in("passes[" + std::to_string(i) + "]");
    for (std::size_t i = 0; i < waypoints.size(); ++i)
        if (Check c = waypoints[i].validate()) return c->in("waypoints[" + std::to_string(i) + "]");
    if (passes.empty() && waypoints.empty())
        return bad("", "is empty: give at least one entry in 'passes' or 'waypoints'");
    return std::nullopt;
}

Check NavigationSpec::validate() const {
    if (Check c = nonNegative(position_noise, "position_noise")) return c;
    if (Check c = nonNegative(depth_noise, "depth_noise")) return c;
    if (Check c = nonNegative(drift_fraction, "drift_fraction")) return c;
    if (!std::isfinite(heading_bias)) return bad("heading_bias_deg", "must be a finite number");
    if (Check c = nonNegative(heading_noise, "heading_noise_deg")) return c;
    if (Check c = nonNegative(attitude_noise, "attitude_noise_deg")) return c;
    if (Check c = nonNegative(latency, "latency")) return c;
    return std::nullopt;
}

Check MotionSpec::validate() const {
    if (Check c = nonNegative(roll_amplitude, "roll_amplitude_deg")) return c;
    if (Check c = nonNegative(pitch_amplitude, "pitch_amplitude_deg")) return c;
    if (Check c = nonNegative(yaw_amplitude, "yaw_amplitude_deg")) return c;
    if (Check c = nonNegative(heave_amplitude, "heave_amplitude")) return c;
    if (Check c = nonNegative(period, "period")) return c;
    if (enabled() && !(period > 0.0)) return bad("period", "must be > 0 when an amplitude is not 0");
    return std::nullopt;
}

Check Channels::validate() const {
    for (const auto& [key, name] :
         {std::pair{"nav", &nav}, std::pair{"fls", &fls}, std::pair{"ps", &ps}, std::pair{"nav_truth", &nav_truth}})
        if (name->empty()) return bad(key, "must not be empty");
    return std::nullopt;
}

Check Scenario::validate() const {
    const std::pair<const char*, Check> blocks[] = {{"scene", scene.validate()},
                                                    {"fls", fls.validate()},
                                                    {"fls", fls_sim.validate()},
                                                    {"fls.mount", fls_mount.validate()},
                                                    {"ps", ps.validate()},
                                                    {"ps", ps_sim.validate()},
                                                    {"ps.mount", ps_mount.validate()},
                                                    {"noise", noise.validate()},
                                                    {"navigation", navigation.validate()},
                                                    {"motion", motion.validate()},
                                                    {"trajectory", trajectory.validate()},
                                                    {"channels", channels.validate()}};
    for (const auto& [block, issue] : blocks)
        if (issue) return issue->in(block);
    if (!fls_sim.window_changes.empty() && !fls.row_range.empty())
        return bad("fls.window_changes", "needs the uniform range bins of Eq. 1 (no fls.row_range)");
    if (publishesTruth() &&
        (channels.nav_truth == channels.nav || channels.nav_truth == channels.fls || channels.nav_truth == channels.ps))
        return bad("channels.nav_truth", "must differ from the nav, fls and ps channels");
    return std::nullopt;
}

double Scenario::trueFaceAngleDeg() const {
    for (const auto& m : scene.meshes)
        if (m.role == MeshRole::Object && m.face_angle_deg > 0.0) return m.face_angle_deg;
    return 0.0;
}


Scenario loadScenarioFromString(const std::string& yaml, const std::string& base_dir) {
    YAML::Node root;
    try {
        root = YAML::Load(yaml);
    } catch (const YAML::Exception& e) {
        throw ScenarioError("(file)", std::string("YAML syntax error: ") + e.what());
    }
    if (!root.IsMap()) throw ScenarioError("(file)", "top level must be a mapping");
    return parseNamingTheField(root, fs::path(base_dir));
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
