// Reads the NAV and NAV_TRUTH samples of an LCM log (sf-eval --log) with the
// project's log reader (apps/common/lcm_log_reader.hpp), for nav_error.hpp.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "nav_error.hpp"

namespace sonarfusion::eval {

struct NavLog {
    std::vector<NavSample> nav, truth;
    int64_t undecodable = 0;  // events on either channel that are not a whole nav_state_t
    bool lost_data = false;   // the reader skipped damaged bytes or a cut tail
};

// Throws std::runtime_error when the file cannot be opened. max_data_len
// bounds one event (as LcmLogReader's); larger events count as damage.
[[nodiscard]] NavLog readNavLog(const std::string& path, const std::string& nav_channel,
                                const std::string& truth_channel, std::size_t max_data_len);

}  // namespace sonarfusion::eval
