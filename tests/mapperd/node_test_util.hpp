// Shared by the daemon-core tests: LCM-encode a message and hand it to a node
// the way the live loop does.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "mapper_node.hpp"

namespace sonarfusion::test {

template <class Msg>
std::vector<uint8_t> encode(const Msg& msg) {
    std::vector<uint8_t> buf(msg.getEncodedSize());
    msg.encode(buf.data(), 0, static_cast<int>(buf.size()));
    return buf;
}

template <class Msg>
void send(MapperNode& node, const std::string& channel, const Msg& msg) {
    const auto b = encode(msg);
    node.handle(channel, b.data(), b.size());
}

}  // namespace sonarfusion::test
