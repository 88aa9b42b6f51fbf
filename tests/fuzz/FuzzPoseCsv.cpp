// FMV pose CSV sidecars: header names, columns, times and angles.
#include "formats/fmv/PoseCsv.h"
#include "tests/fuzz/FuzzInput.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    (void)orbis::fmv::parsePoseCsv(orbis::fuzz::text(data, size), "fuzz.csv");
    return 0;
}
