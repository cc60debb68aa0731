#include "nav_log.hpp"

#include <sonarfusion/nav_state_t.hpp>

#include <stdexcept>

#include "lcm_log_reader.hpp"

namespace sonarfusion::eval {

NavLog readNavLog(const std::string& path, const std::string& nav_channel, const std::string& truth_channel,
                  std::size_t max_data_len) {
    LcmLogReader reader(path, max_data_len);
    if (!reader.good()) throw std::runtime_error("--log " + path + ": cannot open the LCM log");
    NavLog out;
    LcmLogEvent ev;
    while (reader.next(ev)) {
        const bool is_nav = ev.channel == nav_channel;
        if (!is_nav && ev.channel != truth_channel) continue;
        nav_state_t msg{};  // built with -fno-strict-aliasing: see CMakeLists.txt
        if (msg.decode(ev.data, 0, static_cast<int>(ev.size)) != static_cast<int>(ev.size)) {
            ++out.undecodable;
            continue;
        }
        NavSample s;
        s.utime = msg.utime;
        s.position = Eigen::Vector3d(msg.position_ned[0], msg.position_ned[1], msg.position_ned[2]);
        s.roll = msg.rpy[0];
        s.pitch = msg.rpy[1];
        s.yaw = msg.rpy[2];
        (is_nav ? out.nav : out.truth).push_back(s);
    }
    out.lost_data = reader.lostData();
    return out;
}

}  // namespace sonarfusion::eval
