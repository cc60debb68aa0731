// The YAML reading shared by the project's two config formats: the scenario
// (scenario.hpp, docs/scenario-format.md) and the mapper config
// (mapper_config_yaml.hpp, docs/mapper-config.md). Both read their sensor
// blocks (fls, ps, mount) with the functions below, so a block means the same
// in both files. Values are checked by each struct's own validate()
// (sonarfusion/config.hpp); this file only reads.
#pragma once

#include <yaml-cpp/yaml.h>

#include <set>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "sonarfusion/config.hpp"

namespace sonarfusion::config_yaml {

// A key that cannot be read: key() is its full name ("fls.beams"), what() is
// "fls.beams: <problem>".
class KeyError : public std::runtime_error {
public:
    KeyError(const std::string& key, const std::string& problem)
        : std::runtime_error(key + ": " + problem), key_(key), problem_(problem) {}
    [[nodiscard]] const std::string& key() const { return key_; }
    [[nodiscard]] const std::string& problem() const { return problem_; }

private:
    std::string key_, problem_;
};

// A YAML mapping read key by key: remembers which keys were used so that a
// misspelt key is reported (rejectUnknownKeys) instead of silently ignored.
// An absent block, an absent key and a key with no value (null) all leave the
// default.
class Fields {
public:
    // path: the block's name in the file ("fls", "trajectory.passes[0]"; "" for the top level).
    Fields(const YAML::Node& node, std::string path);

    [[nodiscard]] std::string field(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }
    [[nodiscard]] bool has(const std::string& key) const { return node_ && node_.IsMap() && node_[key]; }
    // Marks the key used; an undefined node when absent.
    YAML::Node child(const std::string& key);

    template <class T>
    T get(const std::string& key, T fallback) {
        const YAML::Node n = child(key);
        if (!n.IsDefined() || n.IsNull()) return fallback;
        try {
            return n.as<T>();
        } catch (const YAML::Exception&) {
            throw KeyError(field(key), "cannot read '" + text(n) + "' as " + typeName<T>());
        }
    }
    // Sets `value` when the key is given.
    template <class T>
    void read(const std::string& key, T& value) {
        value = get<T>(key, value);
    }
    // Angles are written in degrees in the files and kept in radians.
    void readDegrees(const std::string& key, double& radians);
    template <class T>
    T require(const std::string& key) {
        if (!has(key)) throw KeyError(field(key), "is required");
        return get<T>(key, T{});
    }

    void rejectUnknownKeys() const;

private:
    static std::string text(const YAML::Node& n);
    template <class T>
    static const char* typeName() {
        if constexpr (std::is_same_v<T, bool>) return "a boolean";
        if constexpr (std::is_integral_v<T>) return "an integer";
        if constexpr (std::is_floating_point_v<T>) return "a number";
        if constexpr (std::is_same_v<T, std::string>) return "a string";
        return "a list";
    }

    YAML::Node node_;
    std::string path_;
    std::set<std::string> used_;
};

// The sensor blocks. Each reads its keys from `f` (other keys of the block,
// such as the simulator's own, are the caller's); none checks values or
// rejects unknown keys: the caller calls validate() and rejectUnknownKeys().
// fls: fov_horizontal_deg, elevation_min_deg, elevation_max_deg, tilt_deg,
//      range_min, range_max, beams, rows, elevation_samples, beam_bearing_deg, row_range
void readFlsGeometry(Fields& f, FlsGeometry& g);
// ps: fan_min_deg, fan_max_deg, head_min_deg, head_max_deg, tilt_deg, range_min,
//     range_max, bins, fan_samples
void readPsGeometry(Fields& f, PsGeometry& g);
// mount: x, y, z, roll_deg, yaw_deg (a whole block: unknown keys rejected, values validated)
void readMounting(const YAML::Node& node, const std::string& path, Mounting& m);

// Throws KeyError(prefix + key, reason) when the struct's validate() finds an issue.
template <class Config>
void requireValid(const Config& c, const std::string& block) {
    if (auto issue = c.validate()) {
        const ConfigIssue full = block.empty() ? *issue : issue->in(block);
        throw KeyError(full.key, full.reason);
    }
}

}  // namespace sonarfusion::config_yaml
