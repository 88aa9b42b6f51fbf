// Trajectory CSV: header detection, columns, units, times; then the trajectory built from it.
#include "formats/motion/TrajectoryCsv.h"
#include "formats/motion/TrajectoryFile.h"
#include "tests/fuzz/FuzzInput.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    (void)orbis::motion::parseTrajectoryCsv(orbis::fuzz::text(data, size), "fuzz.csv");
    orbis::fuzz::MemoryFile file(data, size);
    if (file.ok()) (void)orbis::motion::readTrajectory(file.path());   // sniffed: CSV or GPX
    return 0;
}
