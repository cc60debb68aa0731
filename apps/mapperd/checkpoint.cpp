#include "checkpoint.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <sstream>
#include <stdexcept>

namespace sonarfusion {

namespace {
constexpr char kMagic[8] = {'S', 'F', 'C', 'K', 'P', 'T', '0', '1'};
// 2: survey mode (every map slot, published boxes, detector count); 3: parked maps; 4: above-seabed FLS
// votes per voxel; 5: PS crossings per voxel; 6: held PS pings, which seabed echoes were judged; 7: the
// detector's FLS shadows; 8: held FLS frames; 9: which held frames wait for a seabed
// plane (update.fls_seabed_judged_later), and its counter; 10: the plane the detector judged its newest
// echo against and whether echoes taken before any plane declared (detector.replay_risen_pings_whole);
// 11: each seabed echo's spread down the PS fan (detector.rise_from_deepest_in_beam).
constexpr uint32_t kVersion = 11;

uint64_t fnv1a(const uint8_t* p, std::size_t n, uint64_t h = 1469598103934665603ull) {
    for (std::size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 1099511628211ull;
    return h;
}

template <class T>
void put(uint8_t* at, T v) {
    std::memcpy(at, &v, sizeof(T));
}
template <class T>
T get(const uint8_t* at) {
    T v;
    std::memcpy(&v, at, sizeof(T));
    return v;
}

bool writeAll(int fd, const uint8_t* p, std::size_t n) {
    while (n > 0) {
        const ssize_t k = ::write(fd, p, n);
        if (k < 0) {
            if (errno == EINTR) continue;
            return false;
        }
        p += k, n -= static_cast<std::size_t>(k);
    }
    return true;
}

std::string folderOf(const std::string& path) {
    const auto slash = path.rfind('/');
    return slash == std::string::npos ? "." : (slash == 0 ? "/" : path.substr(0, slash));
}
}  // namespace

uint64_t configFingerprint(const DaemonConfig& d) {
    const MapperConfig& m = d.mapper;
    std::ostringstream s;
    s.precision(17);
    s << d.variant << '|' << m.map.nx << ' ' << m.map.ny << ' ' << m.map.nz << ' ' << m.map.resolution << ' '
      << m.map.clamp_min << ' ' << m.map.clamp_max << ' ' << m.map.snap_to_world_lattice << '|' << m.fls.beams << ' '
      << m.fls.rows << ' ' << m.fls.range_min << ' ' << m.fls.range_max << ' ' << m.fls.tilt << ' '
      << m.fls.fov_horizontal << ' ' << m.fls.elevation_min << ' ' << m.fls.elevation_max << '|' << m.ps.bins << ' '
      << m.ps.range_min << ' ' << m.ps.range_max << ' ' << m.ps.tilt << ' ' << m.ps.fan_min << ' ' << m.ps.fan_max
      << '|' << m.update.p_occupied << ' ' << m.update.p_free << ' ' << m.update.alpha_fls << ' ' << m.update.fls_free_vote_ratio << ' ' << m.update.alpha_ps
      << ' ' << m.update.fls_enabled << m.update.ps_carving_enabled << '|' << m.nav_buffer_capacity << ' '
      << m.nav_timeline_confirm << ' ' << m.max_nav_gap_us << '|' << m.detector.seabed_capacity << ' '
      << m.detector.risen_capacity << ' ' << m.detector.replay_pings << '|' << d.fls_pending_slots << ' ' << d.ps_pending_slots;
    const std::string t = s.str();
    return fnv1a(reinterpret_cast<const uint8_t*>(t.data()), t.size());
}

std::vector<uint8_t> readCheckpoint(const std::string& path, uint64_t fingerprint) {
    auto fail = [&](const std::string& why) { throw std::runtime_error("checkpoint " + path + ": " + why); };
    FILE* f = std::fopen(path.c_str(), "rb");
    if (!f) fail(std::string("cannot open: ") + std::strerror(errno));
    std::vector<uint8_t> all;
    uint8_t chunk[1 << 16];
    std::size_t k;
    while ((k = std::fread(chunk, 1, sizeof(chunk), f)) > 0) {
        if (all.size() + k > (std::size_t{1} << 36)) break;
        all.insert(all.end(), chunk, chunk + k);
    }
    std::fclose(f);
    constexpr std::size_t H = CheckpointWriter::kHeader;
    if (all.size() < H + 8) fail("too short to be a checkpoint (" + std::to_string(all.size()) + " bytes)");
    if (std::memcmp(all.data(), kMagic, 8) != 0) fail("not a sonarfusion checkpoint (bad magic)");
    if (get<uint32_t>(all.data() + 8) != kVersion) fail("unsupported checkpoint version");
    const uint64_t payload = get<uint64_t>(all.data() + 20);
    if (payload != all.size() - H - 8) fail("size field disagrees with the file size (truncated or padded)");
    if (get<uint64_t>(all.data() + H + payload) != fnv1a(all.data(), H + payload)) fail("checksum mismatch (damaged)");
    if (get<uint64_t>(all.data() + 12) != fingerprint)
        fail("made with another config (map size, sonar geometry, variant or capacities differ)");
    return std::vector<uint8_t>(all.begin() + H, all.begin() + static_cast<std::ptrdiff_t>(H + payload));
}

CheckpointWriter::CheckpointWriter(std::string path, std::size_t payload_capacity, uint64_t fingerprint)
    : path_(std::move(path)), fingerprint_(fingerprint), buffer_(kHeader + payload_capacity + 8, 0) {
    thread_ = std::thread([this] { run(); });
}

CheckpointWriter::~CheckpointWriter() {
    {
        std::lock_guard<std::mutex> lock(mu_);
        stop_ = true;
    }
    cv_.notify_all();
    thread_.join();
}

void CheckpointWriter::seal(std::size_t payload_size) {
    uint8_t* b = buffer_.data();
    std::memcpy(b, kMagic, 8);
    put<uint32_t>(b + 8, kVersion);
    put<uint64_t>(b + 12, fingerprint_);
    put<uint64_t>(b + 20, static_cast<uint64_t>(payload_size));
    // The checksum (a few ms over a 5 MB map) is computed on the writer thread.
    {
        std::lock_guard<std::mutex> lock(mu_);
        pending_size_ = kHeader + payload_size + 8;
        busy_ = true;
    }
    cv_.notify_all();
}

void CheckpointWriter::drain() {
    std::unique_lock<std::mutex> lock(mu_);
    cv_.wait(lock, [this] { return !busy_.load(); });
}

void CheckpointWriter::run() {
    std::unique_lock<std::mutex> lock(mu_);
    for (;;) {
        cv_.wait(lock, [this] { return stop_ || busy_.load(); });
        if (busy_.load()) {
            const std::size_t n = pending_size_;
            lock.unlock();
            if (writeFile(n)) ++written_;
            else ++failed_;
            lock.lock();
            busy_ = false;
            cv_.notify_all();
            continue;
        }
        if (stop_) return;
    }
}

bool CheckpointWriter::writeFile(std::size_t total) {
    put<uint64_t>(buffer_.data() + total - 8, fnv1a(buffer_.data(), total - 8));
    const std::string tmp = path_ + ".tmp";
    const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) return false;
    const bool ok = writeAll(fd, buffer_.data(), total) && ::fsync(fd) == 0;
    if (::close(fd) != 0 || !ok || std::rename(tmp.c_str(), path_.c_str()) != 0) {
        std::remove(tmp.c_str());  // the last good checkpoint stays
        return false;
    }
    // The rename itself must reach the disk before the next checkpoint replaces it.
    const int dir = ::open(folderOf(path_).c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dir >= 0) {
        (void)::fsync(dir);
        ::close(dir);
    }
    return true;
}

}  // namespace sonarfusion
