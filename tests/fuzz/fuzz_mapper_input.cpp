// libFuzzer harness for everything the daemon decodes from the network: the
// first byte picks the channel (NAV, FLS or PS), the rest is the raw LCM
// payload handed to MapperNode::handle, exactly as the live loop does.
// Build with clang: see docs/robustness.md.
#include <cstddef>
#include <cstdint>

#include "mapper_node.hpp"

namespace {
sonarfusion::MapperNode& node() {
    static sonarfusion::MapperNode n(sonarfusion::DaemonConfig{}, {});
    return n;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
    if (size < 1) return 0;
    static const char* const kChannels[] = {"NAV", "FLS", "PS"};
    node().handle(kChannels[data[0] % 3], data + 1, size - 1);
    if (data[0] & 0x80) node().flush(true);
    return 0;
}
