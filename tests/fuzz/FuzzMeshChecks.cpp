// The checks Orbis makes on mesh files before Assimp reads them (MeshChecks.h): a PLY header's
// element counts, a COLLADA node graph (cycles, expansion), a KML's model link. The first byte
// picks the check; the rest is the input.
#include "layers/models/MeshChecks.h"

#include <cstddef>
#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size == 0) return 0;
    const std::string_view text(reinterpret_cast<const char*>(data + 1), size - 1);
    switch (data[0] % 3) {
        case 0: (void)orbis::models::checkPlyHeader(text, uint64_t(size) * (data[0] / 3 + 1)); break;
        case 1: (void)orbis::models::checkColladaNodes(text); break;
        default: (void)orbis::models::kmlModelHref(text); break;
    }
    return 0;
}
