// LAS: the header, the VLRs and EVLRs (the CRS through GDAL), and the points of every format,
// read through the same reader as real clouds; then orbis info's description.
#include "layers/points/LasReader.h"
#include "layers/points/PointCloud.h"
#include "tests/fuzz/FuzzInput.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    orbis::fuzz::MemoryFile file(data, size);
    if (!file.ok()) return 0;
    auto las = orbis::points::LasFile::open(file.path());
    if (las) {
        std::vector<orbis::points::LasPoint> points;
        (void)(*las)->read(0, 4096, points);
        (void)(*las)->read((*las)->points() > 8 ? (*las)->points() - 8 : 0, 16, points);
        std::vector<glm::dvec3> positions;
        (void)(*las)->readPositions(0, 4096, positions);
    }
    (void)orbis::points::describeLasJson(file.path());
    return 0;
}
