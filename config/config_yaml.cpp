#include "config_yaml.hpp"

#include <sstream>

namespace sonarfusion::config_yaml {

Fields::Fields(const YAML::Node& node, std::string path) : node_(node), path_(std::move(path)) {
    if (node_ && !node_.IsNull() && !node_.IsMap()) throw KeyError(path_, "must be a mapping");
}

YAML::Node Fields::child(const std::string& key) {
    used_.insert(key);
    return has(key) ? node_[key] : YAML::Node();
}

void Fields::readDegrees(const std::string& key, double& radians) {
    const YAML::Node n = child(key);
    if (!n.IsDefined() || n.IsNull()) return;
    radians = get<double>(key, 0.0) * kDegToRad;
}

void Fields::rejectUnknownKeys() const {
    if (!node_ || !node_.IsMap()) return;
    for (const auto& kv : node_) {
        const std::string key = kv.first.as<std::string>();
        if (!used_.count(key)) throw KeyError(field(key), "unknown key");
    }
}

std::string Fields::text(const YAML::Node& n) {
    if (n.IsScalar()) return n.Scalar();
    std::ostringstream os;
    os << n;
    return os.str();
}

void readFlsGeometry(Fields& f, FlsGeometry& g) {
    f.readDegrees("fov_horizontal_deg", g.fov_horizontal);
    f.readDegrees("elevation_min_deg", g.elevation_min);
    f.readDegrees("elevation_max_deg", g.elevation_max);
    f.readDegrees("tilt_deg", g.tilt);
    f.read("range_min", g.range_min);
    f.read("range_max", g.range_max);
    f.read("beams", g.beams);
    f.read("rows", g.rows);
    f.read("elevation_samples", g.elevation_samples);
    std::vector<double> bearing_deg;
    f.read("beam_bearing_deg", bearing_deg);
    if (!bearing_deg.empty()) {
        g.beam_bearing.clear();
        for (double b : bearing_deg) g.beam_bearing.push_back(b * kDegToRad);
    }
    f.read("row_range", g.row_range);
}

void readPsGeometry(Fields& f, PsGeometry& g) {
    f.readDegrees("fan_min_deg", g.fan_min);
    f.readDegrees("fan_max_deg", g.fan_max);
    f.readDegrees("head_min_deg", g.head_min);
    f.readDegrees("head_max_deg", g.head_max);
    f.readDegrees("tilt_deg", g.tilt);
    f.read("range_min", g.range_min);
    f.read("range_max", g.range_max);
    f.read("bins", g.bins);
    f.read("fan_samples", g.fan_samples);
}

void readMounting(const YAML::Node& node, const std::string& path, Mounting& m) {
    Fields f(node, path);
    f.read("x", m.x);
    f.read("y", m.y);
    f.read("z", m.z);
    f.readDegrees("roll_deg", m.roll);
    f.readDegrees("yaw_deg", m.yaw);
    f.rejectUnknownKeys();
    requireValid(m, path);
}

}  // namespace sonarfusion::config_yaml
