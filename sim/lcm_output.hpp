// Where the simulated messages go: straight into an LCM log file (event time
// stamps = message utime, so lcm-logplayer replays at the simulated pace) or
// live on an LCM bus, paced at real time x rate. Both get the same bytes.
#pragma once

#include <chrono>
#include <cstdint>
#include <lcm/lcm-cpp.hpp>
#include <memory>
#include <string>
#include <vector>

#include "scenario.hpp"
#include "simulator.hpp"

namespace sonarfusion::sim {

template <class Message>
[[nodiscard]] std::vector<uint8_t> encodeMessage(const Message& msg) {
    std::vector<uint8_t> bytes(static_cast<std::size_t>(msg.getEncodedSize()));
    msg.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
    return bytes;
}

class MessageWriter {
public:
    virtual ~MessageWriter() = default;
    virtual void write(const std::string& channel, int64_t utime, const std::vector<uint8_t>& bytes) = 0;
};

class LogWriter : public MessageWriter {
public:
    explicit LogWriter(const std::string& path);  // throws std::runtime_error when it cannot open
    void write(const std::string& channel, int64_t utime, const std::vector<uint8_t>& bytes) override;

private:
    lcm::LogFile log_;
    int64_t eventnum_ = 0;
};

class LivePublisher : public MessageWriter {
public:
    // rate: 1 = real time, 2 = twice as fast, 0 = as fast as possible.
    LivePublisher(const std::string& url, double rate);
    // Publishes on an LCM instance owned by the caller (tests use memq://).
    LivePublisher(lcm::LCM& lcm, double rate);
    void write(const std::string& channel, int64_t utime, const std::vector<uint8_t>& bytes) override;
    // Messages LCM refused to send (best effort: counted, not fatal).
    [[nodiscard]] int64_t failures() const { return failures_; }

private:
    std::unique_ptr<lcm::LCM> owned_;
    lcm::LCM* lcm_;
    int64_t failures_ = 0;
    double rate_;
    bool started_ = false;
    int64_t first_utime_ = 0;
    std::chrono::steady_clock::time_point wall_start_;
};

// Writes one sequence's messages in publish order: NAV first, then NAV_TRUTH
// (when the sequence has it), then PS, then FLS.
void writeSequence(MessageWriter& out, const Channels& channels, const SequenceOutput& seq);

}  // namespace sonarfusion::sim
