// Pictures of simulated data (OpenCV): the FLS frame as stored (beam x range,
// "polar") and as a Cartesian fan, and the PS sector scan as a side-view fan
// plus one ping's intensity against range.
#pragma once

#include <string>
#include <vector>

#include <sonarfusion/fls_image_t.hpp>
#include <sonarfusion/ps_ping_t.hpp>

namespace sonarfusion::sim {

void writeFlsPolarPng(const fls_image_t& frame, const std::string& path);
void writeFlsFanPng(const fls_image_t& frame, const std::string& path);
// `sweep`: consecutive pings (e.g. one sector scan); drawn in the sensor's
// vertical plane, forward to the right and down the page.
void writePsSweepPng(const std::vector<ps_ping_t>& sweep, const std::string& path);
void writePsPingPng(const ps_ping_t& ping, const std::string& path);

}  // namespace sonarfusion::sim
