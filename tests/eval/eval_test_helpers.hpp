// Small meshes for the evaluator tests, written as OFF files to a temp dir.
//
// The dir is private to the test process (its pid in the name) and removed at
// exit: ctest runs every test case as its own process, two at a time with -j2,
// and cases of one suite write the same file names with different contents
// (e.g. every UnitCubeVoxels case writes "unit_cube.off" with its own offset).
// A shared dir let one process truncate and rewrite the file while another
// read it: that case then failed within a millisecond (wrong counts, or an
// unreadable OFF) in a parallel run and never when run alone.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>
#include <vector>

#include <unistd.h>

#include "grid.hpp"
#include "mesh.hpp"

namespace sonarfusion::eval::test {

class ProcessTempDir {
public:
    ProcessTempDir()
        : path_(std::filesystem::temp_directory_path() / ("sf_eval_tests." + std::to_string(::getpid()))) {}
    ~ProcessTempDir() {
        std::error_code ec;
        std::filesystem::remove_all(path_, ec);
    }
    ProcessTempDir(const ProcessTempDir&) = delete;
    ProcessTempDir& operator=(const ProcessTempDir&) = delete;
    [[nodiscard]] const std::filesystem::path& path() const { return path_; }

private:
    std::filesystem::path path_;
};

inline std::string tempDir() {
    static const ProcessTempDir dir;
    std::filesystem::create_directories(dir.path());
    return dir.path().string();
}

// Writes an OFF with the given vertices and polygons; returns its path.
inline std::string writeOff(const std::string& name, const std::vector<Eigen::Vector3d>& v,
                            const std::vector<std::vector<int>>& faces) {
    const std::string path = tempDir() + "/" + name + ".off";
    std::ofstream f(path);
    f.precision(17);
    f << "OFF\n" << v.size() << ' ' << faces.size() << " 0\n";
    for (const auto& p : v) f << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
    for (const auto& face : faces) {
        f << face.size();
        for (int i : face) f << ' ' << i;
        f << '\n';
    }
    return path;
}

// Slope box in NED (z down): base [x0, x0+base] x [y0, y0+width] at depth
// z_bottom, height h, both x end faces inclined at alpha (deg) from horizontal.
// Quads as faces, outward-oriented (CGAL's reader fan-triangulates them).
inline std::string writeSlopeBox(const std::string& name, const Eigen::Vector3d& base_min, double base,
                                 double width, double height, double alpha_deg) {
    const double inset = alpha_deg == 90.0 ? 0.0 : height / std::tan(alpha_deg * M_PI / 180.0);
    const double x0 = base_min.x(), y0 = base_min.y(), zb = base_min.z(), zt = zb - height;
    const double x1 = x0 + base, y1 = y0 + width;
    std::vector<Eigen::Vector3d> v = {
        {x0, y0, zb}, {x1, y0, zb}, {x1, y1, zb}, {x0, y1, zb},                          // bottom 0..3
        {x0 + inset, y0, zt}, {x1 - inset, y0, zt}, {x1 - inset, y1, zt}, {x0 + inset, y1, zt}};  // top 4..7
    // Outward orientation does not matter for the inside test; keep it consistent anyway.
    std::vector<std::vector<int>> f = {{0, 1, 2, 3}, {4, 7, 6, 5}, {0, 4, 5, 1},
                                       {1, 5, 6, 2}, {2, 6, 7, 3}, {3, 7, 4, 0}};
    return writeOff(name, v, f);
}

// Axis-aligned box [lo, hi].
inline std::string writeBox(const std::string& name, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
    return writeSlopeBox(name, Eigen::Vector3d(lo.x(), lo.y(), hi.z()), hi.x() - lo.x(), hi.y() - lo.y(),
                         hi.z() - lo.z(), 90.0);
}

inline GridSpec grid(const Eigen::Vector3d& origin, int n, double res = 0.1) {
    return GridSpec{origin, res, n, n, n};
}

}  // namespace sonarfusion::eval::test
