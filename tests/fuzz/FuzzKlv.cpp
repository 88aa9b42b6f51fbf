// MISB ST 0601 KLV: a raw stream (resynchronisation, BER lengths, local sets, nested ST 0102
// and other sets, checksums) and each decoded packet written as orbis info's JSON line.
#include "formats/fmv/KlvFile.h"
#include "formats/fmv/St0601.h"
#include "tests/fuzz/FuzzInput.h"

#include <nlohmann/json.hpp>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const orbis::fmv::KlvStream stream = orbis::fmv::decodeKlvStream(orbis::fmv::Bytes(data, size));
    for (const orbis::fmv::KlvRecord& r : stream.records)
        if (r.packet) (void)nlohmann::json::parse(orbis::fmv::st0601JsonLine(*r.packet, r.offset));
    return 0;
}
