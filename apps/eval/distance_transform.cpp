#include "distance_transform.hpp"

#include <limits>

namespace sonarfusion::eval {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();

// 1-D squared distance transform of f (n samples) into d; v, z are scratch.
void transform1d(const double* f, double* d, int n, std::vector<int>& v, std::vector<double>& z) {
    int k = 0;
    int first = -1;
    for (int q = 0; q < n; ++q)
        if (f[q] < kInf) {
            first = q;
            break;
        }
    if (first < 0) {
        for (int q = 0; q < n; ++q) d[q] = kInf;
        return;
    }
    v[0] = first;
    z[0] = -kInf;
    z[1] = kInf;
    for (int q = first + 1; q < n; ++q) {
        if (f[q] == kInf) continue;
        double s;
        for (;;) {
            const int p = v[k];
            s = ((f[q] + q * static_cast<double>(q)) - (f[p] + p * static_cast<double>(p))) / (2.0 * (q - p));
            if (s <= z[k] && k > 0) {
                --k;
                continue;
            }
            break;
        }
        ++k;
        v[k] = q;
        z[k] = s;
        z[k + 1] = kInf;
    }
    k = 0;
    for (int q = 0; q < n; ++q) {
        while (z[k + 1] < q) ++k;
        const double dq = q - v[k];
        d[q] = dq * dq + f[v[k]];
    }
}
}  // namespace

std::vector<double> squaredDistanceToSet(const GridSpec& g, const VoxelMask& mask) {
    std::vector<double> dist(g.size());
    for (std::size_t i = 0; i < g.size(); ++i) dist[i] = mask[i] ? 0.0 : kInf;
    const int nmax = std::max(g.nx, std::max(g.ny, g.nz));
    std::vector<double> in(nmax), out(nmax), z(nmax + 1);
    std::vector<int> v(nmax);
    const std::size_t stride[3] = {1, static_cast<std::size_t>(g.nx), static_cast<std::size_t>(g.nx) * g.ny};
    const int len[3] = {g.nx, g.ny, g.nz};
    for (int axis = 0; axis < 3; ++axis) {
        const int n = len[axis];
        const std::size_t s = stride[axis];
        // Every line along `axis`: its start is any voxel whose coordinate on `axis` is 0.
        for (std::size_t start = 0; start < g.size(); ++start) {
            if ((start / s) % n != 0) continue;
            for (int q = 0; q < n; ++q) in[q] = dist[start + q * s];
            transform1d(in.data(), out.data(), n, v, z);
            for (int q = 0; q < n; ++q) dist[start + q * s] = out[q];
        }
    }
    return dist;
}

}  // namespace sonarfusion::eval
