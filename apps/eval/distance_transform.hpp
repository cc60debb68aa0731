// Exact Euclidean distance transform on the grid (Felzenszwalb & Huttenlocher,
// separable lower envelope of parabolas): for every voxel, the distance from
// its centre to the nearest centre of a set voxel. O(voxels).
#pragma once

#include <vector>

#include "grid.hpp"

namespace sonarfusion::eval {

// Squared distances in voxel units (1 = face neighbour, 2 = edge neighbour);
// +infinity everywhere when the mask is empty.
[[nodiscard]] std::vector<double> squaredDistanceToSet(const GridSpec& grid, const VoxelMask& mask);

}  // namespace sonarfusion::eval
