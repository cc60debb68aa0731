// libFuzzer harness for the checkpoint loader (apps/mapperd/checkpoint.hpp) the
// way `sf-mapper --resume` uses it: readCheckpoint (magic, version, size,
// checksum, config fingerprint) and MapperNode::loadState on its payload. The
// checksum would stop nearly every mutation at the first step, so the input's
// first byte chooses: odd, the bytes are a checkpoint file; even, the rest is
// a payload handed to loadState directly. A small map (8^3) keeps valid states
// a few kB. Any bad input must be a std::runtime_error or a false from
// loadState; a state that loads must save and load again.
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <vector>

#include "checkpoint.hpp"
#include "checkpoint_fuzz_config.hpp"
#include "fuzz_util.hpp"
#include "mapper_node.hpp"

using namespace sonarfusion;


extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
    if (size < 1) return 0;
    static const DaemonConfig cfg = sffuzz::checkpointFuzzConfig();
    std::vector<uint8_t> payload;
    if (data[0] & 1) {
        try {
            payload = readCheckpoint(sffuzz::asFile(data + 1, size - 1), configFingerprint(cfg));
        } catch (const std::runtime_error&) {
            return 0;
        }
    } else {
        payload.assign(data + 1, data + size);
    }
    MapperNode node(cfg, {});
    StateReader r(payload.data(), payload.size());
    if (!node.loadState(r)) return 0;
    std::vector<uint8_t> again(node.stateBytesBound());
    StateWriter w(again.data(), again.size());
    node.saveState(w);
    if (w.overflow()) __builtin_trap();
    again.resize(w.size());
    MapperNode second(cfg, {});
    StateReader r2(again.data(), again.size());
    if (!second.loadState(r2)) __builtin_trap();  // what we wrote must load
    return 0;
}
