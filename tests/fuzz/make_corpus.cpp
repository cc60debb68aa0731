// Writes valid NAV, FLS and PS encodings (with the channel byte in front) as a
// seed corpus for fuzz_mapper_input, so the fuzzer starts past the fingerprint.
#include <cstdio>
#include <string>
#include <vector>

#include <sonarfusion/fls_image_t.hpp>
#include <sonarfusion/nav_state_t.hpp>
#include <sonarfusion/ps_ping_t.hpp>

template <class Msg>
void write(const std::string& dir, const char* name, uint8_t channel, const Msg& m) {
    std::vector<uint8_t> buf(1 + m.getEncodedSize());
    buf[0] = channel;
    m.encode(buf.data() + 1, 0, static_cast<int>(buf.size() - 1));
    FILE* f = std::fopen((dir + "/" + name).c_str(), "wb");
    if (!f) return;
    std::fwrite(buf.data(), 1, buf.size(), f);
    std::fclose(f);
}

int main(int argc, char** argv) {
    if (argc != 2) return 2;
    sonarfusion::nav_state_t nav{};
    nav.utime = 1000;
    nav.position_ned[2] = 16.9;
    write(argv[1], "nav", 0, nav);
    sonarfusion::fls_image_t fls{};
    fls.utime = 1000;
    fls.num_beams = 4;
    fls.beam_bearing.assign(4, 0.1f);
    fls.num_ranges = 8;
    fls.row_range.assign(8, 2.0f);
    fls.data_size = 32;
    fls.data.assign(32, static_cast<int8_t>(-56));
    write(argv[1], "fls", 1, fls);
    sonarfusion::ps_ping_t ps{};
    ps.utime = 1000;
    ps.range_max = 10.0f;
    ps.num_bins = 50;
    ps.intensity.assign(50, 20);
    write(argv[1], "ps", 2, ps);
    return 0;
}
