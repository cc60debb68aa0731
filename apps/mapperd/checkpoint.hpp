// Crash-safe checkpoints of the daemon (issue 10): the whole state MapperNode
// needs to go on, written atomically (temporary file, fsync, rename, fsync of
// the folder) with a checksum, from a buffer allocated at start-up, by a
// background thread so the message loop never waits on the disk.
//
// File layout (little-endian): "SFCKPT01", u32 version, u64 config fingerprint,
// u64 payload size, payload (MapperNode::saveState), u64 FNV-1a 64 of all the
// bytes before it.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "mapper_config_yaml.hpp"
#include "sonarfusion/state_codec.hpp"

namespace sonarfusion {

// Settings a checkpoint must have been made with to be loaded by this config.
[[nodiscard]] uint64_t configFingerprint(const DaemonConfig& cfg);

// Reads and checks a checkpoint; returns its payload. Throws std::runtime_error
// naming the file and what is wrong (missing, short, bad magic/version,
// checksum, or another config).
[[nodiscard]] std::vector<uint8_t> readCheckpoint(const std::string& path, uint64_t fingerprint);

class CheckpointWriter {
public:
    // Allocates the buffer (header + payload_capacity) and starts the writer thread.
    CheckpointWriter(std::string path, std::size_t payload_capacity, uint64_t fingerprint);
    ~CheckpointWriter();
    CheckpointWriter(const CheckpointWriter&) = delete;
    CheckpointWriter& operator=(const CheckpointWriter&) = delete;

    // Fills the buffer with `fill(StateWriter&)` and hands it to the writer
    // thread. When the previous write is still running it returns false and
    // counts a skip (the next period tries again). `fill` runs on this thread.
    template <class Fill>
    bool submit(Fill&& fill) {
        if (busy_.load()) {
            ++skipped_;
            return false;
        }
        StateWriter w(buffer_.data() + kHeader, buffer_.size() - kHeader - 8);
        fill(w);
        if (w.overflow()) {
            ++failed_;
            return false;
        }
        seal(w.size());
        return true;
    }
    // Waits until the writer thread is idle (then the last submitted file is on disk or failed).
    void drain();

    [[nodiscard]] int64_t written() const { return written_.load(); }
    [[nodiscard]] int64_t failed() const { return failed_.load(); }
    [[nodiscard]] int64_t skipped() const { return skipped_.load(); }
    [[nodiscard]] const std::string& path() const { return path_; }

    static constexpr std::size_t kHeader = 8 + 4 + 8 + 8;

private:
    void seal(std::size_t payload_size);
    void run();
    bool writeFile(std::size_t total);

    std::string path_;
    uint64_t fingerprint_;
    std::vector<uint8_t> buffer_;
    std::size_t pending_size_ = 0;
    std::atomic<bool> busy_{false};
    std::atomic<int64_t> written_{0}, failed_{0}, skipped_{0};
    std::mutex mu_;
    std::condition_variable cv_;
    bool stop_ = false;
    std::thread thread_;
};

}  // namespace sonarfusion
