// LAS, LAZ and COPC: the header, the VLRs and EVLRs (the CRS through GDAL), the LAZ chunk table
// and chunks (every compressor), a COPC file's hierarchy pages and nodes, and the points of every
// format, read through the same reader as real clouds; then orbis info's description.
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
        // COPC: the hierarchy pages and the first nodes' chunks.
        if ((*las)->copc()) {
            auto nodes = orbis::points::copc::readHierarchy(**las, *(*las)->copc());
            if (nodes)
                for (size_t i = 0; i < nodes->size() && i < 4; ++i)
                    (void)(*las)->readChunk((*nodes)[i].offset, (*nodes)[i].bytes, (*nodes)[i].points, points);
        }
    }
    (void)orbis::points::describeLasJson(file.path());
    return 0;
}
