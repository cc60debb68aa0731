#include "lcm_output.hpp"

#include <stdexcept>
#include <thread>

namespace sonarfusion::sim {

LogWriter::LogWriter(const std::string& path) : log_(path, "w") {
    if (!log_.good()) throw std::runtime_error("cannot open LCM log for writing: " + path);
}

void LogWriter::write(const std::string& channel, int64_t utime, const std::vector<uint8_t>& bytes) {
    lcm::LogEvent event;
    event.eventnum = eventnum_++;
    event.timestamp = utime;
    event.channel = channel;
    event.datalen = static_cast<int32_t>(bytes.size());
    event.data = const_cast<uint8_t*>(bytes.data());  // LCM's API is not const-correct; it only reads
    if (log_.writeEvent(&event) != 0) throw std::runtime_error("writing the LCM log failed");
}

LivePublisher::LivePublisher(const std::string& url, double rate)
    : owned_(std::make_unique<lcm::LCM>(url)), lcm_(owned_.get()), rate_(rate) {
    if (!lcm_->good()) throw std::runtime_error("cannot open LCM" + (url.empty() ? std::string() : " at " + url));
    if (rate < 0.0) throw std::invalid_argument("--rate must be >= 0");
}

LivePublisher::LivePublisher(lcm::LCM& lcm, double rate) : lcm_(&lcm), rate_(rate) {
    if (!lcm_->good()) throw std::runtime_error("LCM instance is not usable");
    if (rate < 0.0) throw std::invalid_argument("--rate must be >= 0");
}

void LivePublisher::write(const std::string& channel, int64_t utime, const std::vector<uint8_t>& bytes) {
    if (!started_) {
        started_ = true;
        first_utime_ = utime;
        wall_start_ = std::chrono::steady_clock::now();
    }
    if (rate_ > 0.0) {
        const auto due = wall_start_ + std::chrono::microseconds(
                                           static_cast<int64_t>(static_cast<double>(utime - first_utime_) / rate_));
        std::this_thread::sleep_until(due);
    }
    if (lcm_->publish(channel, bytes.data(), static_cast<unsigned>(bytes.size())) != 0) ++failures_;
}

void writeSequence(MessageWriter& out, const Channels& channels, const SequenceOutput& seq) {
    out.write(channels.nav, seq.nav.utime, encodeMessage(seq.nav));
    if (seq.has_truth) out.write(channels.nav_truth, seq.truth.utime, encodeMessage(seq.truth));
    out.write(channels.ps, seq.ps.utime, encodeMessage(seq.ps));
    if (seq.has_fls) out.write(channels.fls, seq.fls.utime, encodeMessage(seq.fls));
}

}  // namespace sonarfusion::sim
