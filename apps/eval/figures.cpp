#include "figures.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <optional>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "map_file.hpp"

namespace sonarfusion::eval {

namespace {
constexpr double kPixelsPerMetre = 120.0;
constexpr int kLeft = 80, kRight = 110, kTop = 46, kBottom = 56;
const cv::Scalar kWhite(255, 255, 255), kBlack(0, 0, 0), kRed(0, 0, 220), kGrey(140, 140, 140);

// World window shown in every panel: the objects plus room for false slopes.
struct Window {
    double x0, x1, y0, y1, z0, z1;
};

// An object-free scene (nothing to outline) shows the whole extent of the
// initialised maps instead, where any (false) object would be.
std::optional<Window> windowAround(const SceneTruth& scene, const std::vector<FigurePanel>& panels) {
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (const auto& m : scene.objects) {
        Eigen::Vector3d a, b;
        meshBounds(m, a, b);
        lo = lo.cwiseMin(a);
        hi = hi.cwiseMax(b);
    }
    if (!lo.allFinite()) {
        for (const FigurePanel& p : panels)
            if (p.map != nullptr && p.map->initialised()) {
                lo = lo.cwiseMin(p.map->origin());
                hi = hi.cwiseMax(p.map->origin() + p.map->extent());
            }
        if (!lo.allFinite()) return std::nullopt;  // no object, no map: nothing to draw
        return Window{std::floor(lo.x()), std::ceil(hi.x()), std::floor(lo.y()), std::ceil(hi.y()), std::floor(lo.z()),
                std::ceil(hi.z())};
    }
    return Window{std::floor(lo.x() - 1.5), std::ceil(hi.x() + 1.5), std::floor(lo.y() - 1.0), std::ceil(hi.y() + 1.0),
            std::floor(lo.z() - 1.0), std::ceil(hi.z() + 0.5)};
}

// One projection: horizontal axis world x, vertical axis world z (side) or y (top).
struct View {
    bool side;
    Window w;
    [[nodiscard]] double v0() const { return side ? w.z0 : w.y0; }
    [[nodiscard]] double v1() const { return side ? w.z1 : w.y1; }
    [[nodiscard]] int plotWidth() const { return static_cast<int>(std::lround((w.x1 - w.x0) * kPixelsPerMetre)); }
    [[nodiscard]] int plotHeight() const { return static_cast<int>(std::lround((v1() - v0()) * kPixelsPerMetre)); }
    [[nodiscard]] cv::Point2d pixel(double x, double v) const {
        return {kLeft + (x - w.x0) * kPixelsPerMetre, kTop + (v - v0()) * kPixelsPerMetre};
    }
    [[nodiscard]] double vertical(const Eigen::Vector3d& p) const { return side ? p.z() : p.y(); }
    [[nodiscard]] double across(const Eigen::Vector3d& p) const { return side ? p.y() : p.z(); }
};

cv::Vec3b viridis(double t) {
    static cv::Mat lut;
    if (lut.empty()) {
        cv::Mat ramp(1, 256, CV_8UC1);
        for (int i = 0; i < 256; ++i) ramp.at<uint8_t>(0, i) = static_cast<uint8_t>(i);
        cv::applyColorMap(ramp, lut, cv::COLORMAP_VIRIDIS);
    }
    return lut.at<cv::Vec3b>(0, std::clamp(static_cast<int>(std::lround(t * 255.0)), 0, 255));
}

void text(cv::Mat& img, const std::string& s, cv::Point at, double scale = 0.45, int thickness = 1) {
    cv::putText(img, s, at, cv::FONT_HERSHEY_SIMPLEX, scale, kBlack, thickness, cv::LINE_AA);
}

std::string metres(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.1f", v);
    return buf;
}

// Silhouette of meshes in the view, as contours of their filled projection.
void drawSilhouette(cv::Mat& img, const View& view, const std::vector<TriangleMesh>& meshes, const cv::Scalar& colour,
                    int thickness, bool only_inside_window) {
    cv::Mat mask(img.size(), CV_8UC1, cv::Scalar(0));
    for (const auto& m : meshes)
        for (const auto& t : m.triangles) {
            std::vector<cv::Point> poly;
            Eigen::Vector3d mid = Eigen::Vector3d::Zero();
            for (int k = 0; k < 3; ++k) {
                const Eigen::Vector3d& p = m.vertices[t[k]];
                mid += p / 3.0;
                poly.emplace_back(view.pixel(p.x(), view.vertical(p)) * 4.0);  // 2 bits of sub-pixel
            }
            const double a = view.across(mid);
            if (only_inside_window && (a < (view.side ? view.w.y0 : view.w.z0) || a > (view.side ? view.w.y1 : view.w.z1)))
                continue;
            cv::fillConvexPoly(mask, poly, cv::Scalar(255), cv::LINE_8, 2);
        }
    std::vector<std::vector<cv::Point>> contours;
    cv::findContours(mask, contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_SIMPLE);
    cv::polylines(img, contours, true, colour, thickness, cv::LINE_AA);
}

void drawAxes(cv::Mat& img, const View& view, const std::string& title, const std::string& bar_label, int max_count) {
    const int w = view.plotWidth(), h = view.plotHeight();
    cv::rectangle(img, {kLeft, kTop}, {kLeft + w, kTop + h}, kBlack, 1);
    for (double x = std::ceil(view.w.x0 * 2) / 2; x <= view.w.x1 + 1e-9; x += 0.5) {
        const cv::Point p = view.pixel(x, view.v1());
        cv::line(img, p, p + cv::Point(0, 5), kBlack, 1);
        text(img, metres(x), p + cv::Point(-14, 20));
    }
    for (double v = std::ceil(view.v0() * 2) / 2; v <= view.v1() + 1e-9; v += 0.5) {
        const cv::Point p = view.pixel(view.w.x0, v);
        cv::line(img, p, p - cv::Point(5, 0), kBlack, 1);
        text(img, metres(v), p + cv::Point(-48, 5));
    }
    text(img, "x (north, along-track) [m]", {kLeft + w / 2 - 100, kTop + h + 45});
    text(img, view.side ? "depth z [m]" : "y (east) [m]", {6, kTop - 6});
    text(img, title, {kLeft, 18}, 0.55, 1);
    // Colour bar: 1 .. max_count voxels along the projection axis.
    const int bx = kLeft + w + 20, bh = std::max(60, h - 20);
    for (int r = 0; r < bh; ++r) {
        const cv::Vec3b c = viridis(1.0 - static_cast<double>(r) / (bh - 1));
        cv::line(img, {bx, kTop + r}, {bx + 16, kTop + r}, cv::Scalar(c[0], c[1], c[2]), 1);
    }
    cv::rectangle(img, {bx, kTop}, {bx + 16, kTop + bh}, kBlack, 1);
    text(img, std::to_string(max_count), {bx + 20, kTop + 10});
    text(img, "1", {bx + 20, kTop + bh});
    text(img, bar_label, {bx - 10, kTop + bh + 18}, 0.4);
}

// objects_only: count the voxels the segmentation reports as objects (the set P
// that is scored) instead of every occupied voxel.
cv::Mat drawProjection(const View& view, const FigurePanel& panel, const SceneTruth& scene, const std::string& title,
                       bool objects_only) {
    const VoxelMap& map = *panel.map;
    const GridSpec grid = GridSpec::of(map);
    const GroundTruth& gt = *panel.truth;
    // Top view: only voxels above the true seabed (else the seabed hides all).
    std::vector<double> seabed_top(static_cast<std::size_t>(grid.nx) * grid.ny, std::numeric_limits<double>::infinity());
    for (std::size_t i = 0; i < grid.size(); ++i)
        if (gt.seabed.solid[i]) {
            const Eigen::Vector3i v = grid.index(i);
            double& top = seabed_top[static_cast<std::size_t>(v.y()) * grid.nx + v.x()];
            top = std::min(top, grid.centre(i).z());
        }
    // Count occupied (or object) voxels per (ix, i_vertical) cell of the projection.
    const VoxelMask& shown = objects_only ? panel.prediction->object : panel.prediction->occupied;
    const int nv = view.side ? grid.nz : grid.ny;
    std::vector<int> count(static_cast<std::size_t>(grid.nx) * nv, 0);
    for (std::size_t i = 0; i < grid.size(); ++i) {
        if (!shown[i]) continue;
        const Eigen::Vector3d c = grid.centre(i);
        const Eigen::Vector3i v = grid.index(i);
        if (c.x() < view.w.x0 || c.x() > view.w.x1 || c.y() < view.w.y0 || c.y() > view.w.y1 || c.z() < view.w.z0 ||
            c.z() > view.w.z1)
            continue;
        if (!view.side && c.z() > seabed_top[static_cast<std::size_t>(v.y()) * grid.nx + v.x()] - grid.resolution)
            continue;
        ++count[static_cast<std::size_t>(view.side ? v.z() : v.y()) * grid.nx + v.x()];
    }
    const int max_count = std::max(1, *std::max_element(count.begin(), count.end()));
    cv::Mat img(kTop + view.plotHeight() + kBottom, kLeft + view.plotWidth() + kRight, CV_8UC3, kWhite);
    cv::Mat plot = img(cv::Rect(kLeft, kTop, view.plotWidth(), view.plotHeight()));
    for (int iv = 0; iv < nv; ++iv)
        for (int ix = 0; ix < grid.nx; ++ix) {
            const int n = count[static_cast<std::size_t>(iv) * grid.nx + ix];
            if (n == 0) continue;
            const double x = grid.origin.x() + ix * grid.resolution;
            const double v = (view.side ? grid.origin.z() : grid.origin.y()) + iv * grid.resolution;
            const cv::Point a = view.pixel(x, v) - cv::Point2d(kLeft, kTop);
            const cv::Point b = view.pixel(x + grid.resolution, v + grid.resolution) - cv::Point2d(kLeft, kTop);
            const cv::Vec3b c = viridis(max_count == 1 ? 1.0 : (n - 1.0) / (max_count - 1.0));
            cv::rectangle(plot, a, b - cv::Point(1, 1), cv::Scalar(c[0], c[1], c[2]), cv::FILLED);
        }
    if (view.side) drawSilhouette(img, view, scene.seabed, kGrey, 1, true);
    drawSilhouette(img, view, scene.objects, kRed, 2, false);
    drawAxes(img, view, title, view.side ? "voxels along y" : "voxels along z", max_count);
    return img;
}
}  // namespace

std::vector<std::string> writeFigures(const std::string& dir, const std::string& scenario, const SceneTruth& scene,
                                      const std::vector<FigurePanel>& panels) {
    std::filesystem::create_directories(dir);
    std::vector<std::string> written;
    const std::optional<Window> around = windowAround(scene, panels);
    if (!around) return written;
    const Window window = *around;
    for (bool objects_only : {false, true})
        for (bool side : {true, false}) {
            const View view{side, window};
            const std::string suffix = std::string(side ? "_side" : "_top") + (objects_only ? "_objects" : "");
            std::vector<cv::Mat> images;
            for (const FigurePanel& p : panels) {
                const std::string title = scenario + "  " + p.variant + ": " + (side ? "side view" : "top view") +
                                          (objects_only ? ", object voxels" : ", occupied voxels") + ", true outline red";
                images.push_back(drawProjection(view, p, scene, title, objects_only));
                const std::string path = dir + "/eval_" + p.variant + suffix + ".png";
                if (!cv::imwrite(path, images.back())) throw std::runtime_error("figures: cannot write " + path);
                written.push_back(path);
            }
            if (images.size() > 1) {
                cv::Mat all;
                cv::vconcat(images, all);
                const std::string path = dir + "/eval" + suffix + "_all.png";
                if (!cv::imwrite(path, all)) throw std::runtime_error("figures: cannot write " + path);
                written.push_back(path);
            }
        }
    return written;
}

std::vector<std::string> writePointClouds(const std::string& dir, const FigurePanel& panel, bool with_truth) {
    std::filesystem::create_directories(dir);
    const VoxelMap& map = *panel.map;
    const double threshold = 0.5;  // the masks below already hold the decision
    std::vector<std::string> written;
    auto labels = [](const VoxelMask& m) { return std::vector<int32_t>(m.begin(), m.end()); };
    // A map whose every voxel is certain, filtered by a mask: reuses savePly.
    MapConfig cfg{map.nx(), map.ny(), map.nz(), map.resolution(), map.clampMin(), map.clampMax()};
    VoxelMap full(cfg);
    full.initialiseAt(map.origin() + 0.5 * map.extent());
    for (std::size_t i = 0; i < full.size(); ++i) full.setLogOdds(i, full.clampMax());
    const std::pair<std::string, const VoxelMask*> clouds[] = {
        {panel.variant + "_occupied.ply", &panel.prediction->occupied},
        {panel.variant + "_objects.ply", &panel.prediction->object},
        {"gt_object.ply", with_truth ? &panel.truth->object.solid : nullptr},
        {"gt_visible.ply", with_truth ? &panel.truth->visible : nullptr}};
    for (const auto& [name, mask] : clouds) {
        if (!mask) continue;
        const std::vector<int32_t> keep = labels(*mask);
        savePly(dir + "/" + name, full, threshold, &keep);
        written.push_back(dir + "/" + name);
    }
    return written;
}

}  // namespace sonarfusion::eval
