#include "png_export.hpp"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace sonarfusion::sim {

namespace {

void save(const cv::Mat& image, const std::string& path) {
    if (!cv::imwrite(path, image)) throw std::runtime_error("cannot write " + path);
}

// Index of the entry of `values` nearest to v, or -1 when v lies more than
// half a spacing beyond either end.
int nearestIndex(const std::vector<float>& values, double v) {
    if (values.size() < 2) return values.empty() ? -1 : 0;
    int best = 0;
    for (int i = 1; i < static_cast<int>(values.size()); ++i)
        if (std::fabs(values[i] - v) < std::fabs(values[best] - v)) best = i;
    const double spacing = std::fabs(values[1] - values[0]);
    const double lo = std::min(values.front(), values.back()), hi = std::max(values.front(), values.back());
    return (v < lo - 0.5 * spacing || v > hi + 0.5 * spacing) ? -1 : best;
}

cv::Mat colourise(const cv::Mat& grey) {
    cv::Mat out;
    cv::applyColorMap(grey, out, cv::COLORMAP_INFERNO);
    return out;
}

}  // namespace

void writeFlsPolarPng(const fls_image_t& f, const std::string& path) {
    const cv::Mat grey(f.num_ranges, f.num_beams, CV_8UC1, const_cast<uint8_t*>(f.data.data()));
    cv::Mat wide;
    cv::resize(grey, wide, cv::Size(f.num_beams * 4, f.num_ranges), 0, 0, cv::INTER_NEAREST);
    save(colourise(wide), path);
}

void writeFlsFanPng(const fls_image_t& f, const std::string& path) {
    const double r_max = *std::max_element(f.row_range.begin(), f.row_range.end());
    const double half_fov = std::max(std::fabs(f.beam_bearing.front()), std::fabs(f.beam_bearing.back()));
    const int height = 512;
    const double px_per_m = height / r_max;
    const int half_width = static_cast<int>(std::ceil(r_max * std::sin(half_fov) * px_per_m)) + 2;
    cv::Mat grey(height, 2 * half_width + 1, CV_8UC1, cv::Scalar(0));
    // Bearings and ranges are sorted in the message, so a nearest lookup per
    // output pixel is exact; the table is small enough to search linearly.
    std::vector<float> bearing_by_col(f.beam_bearing.begin(), f.beam_bearing.end());
    for (int v = 0; v < height; ++v) {
        const double forward = (height - 1 - v) / px_per_m;  // sonar at the bottom centre
        for (int u = 0; u < grey.cols; ++u) {
            const double starboard = (u - half_width) / px_per_m;
            const int col = nearestIndex(bearing_by_col, std::atan2(starboard, forward));
            const int row = nearestIndex(f.row_range, std::hypot(forward, starboard));
            if (col >= 0 && row >= 0) grey.at<uint8_t>(v, u) = f.data[static_cast<std::size_t>(row) * f.num_beams + col];
        }
    }
    save(colourise(grey), path);
}

void writePsSweepPng(const std::vector<ps_ping_t>& sweep, const std::string& path) {
    if (sweep.empty()) throw std::invalid_argument("writePsSweepPng: no pings");
    const ps_ping_t& first = sweep.front();
    const int size = 500;
    const double px_per_m = size / first.range_max;
    cv::Mat grey(size, size, CV_8UC1, cv::Scalar(0));
    std::vector<float> head;
    for (const auto& p : sweep) head.push_back(p.head_angle);
    const double step = sweep.size() > 1 ? std::fabs(head[1] - head[0]) : 0.02;
    for (int v = 0; v < size; ++v) {
        for (int u = 0; u < size; ++u) {
            const double forward = u / px_per_m, down = v / px_per_m;
            const double range = std::hypot(forward, down);
            const double phi_p = std::atan2(down, forward) - first.tilt;
            int best = -1;
            for (int i = 0; i < static_cast<int>(head.size()); ++i)
                if (std::fabs(head[i] - phi_p) <= 0.5 * step + 1e-6 && (best < 0 || sweep[i].seq > sweep[best].seq))
                    best = i;  // the newest ping at that head angle
            if (best < 0) continue;
            const ps_ping_t& p = sweep[best];
            const double t = (range - p.range_min) / (p.range_max - p.range_min) * (p.num_bins - 1);
            const long bin = std::lround(t);
            if (bin >= 0 && bin < p.num_bins) grey.at<uint8_t>(v, u) = p.intensity[bin];
        }
    }
    save(colourise(grey), path);
}

void writePsPingPng(const ps_ping_t& p, const std::string& path) {
    const int width = std::max(500, p.num_bins), height = 256 + 20;
    cv::Mat plot(height, width, CV_8UC3, cv::Scalar(255, 255, 255));
    cv::line(plot, {0, height - 10 - 150}, {width - 1, height - 10 - 150}, cv::Scalar(180, 180, 255), 1);  // 150
    std::vector<cv::Point> line;
    for (int b = 0; b < p.num_bins; ++b)
        line.emplace_back(b * (width - 1) / std::max(1, p.num_bins - 1), height - 10 - p.intensity[b]);
    cv::polylines(plot, line, false, cv::Scalar(40, 40, 40), 1, cv::LINE_AA);
    save(plot, path);
}

}  // namespace sonarfusion::sim
