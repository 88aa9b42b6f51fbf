// glTF 2.0 (binary .glb, or JSON with data URIs) through Orbis's conversion to a model: buffers,
// accessors, images, materials, nodes, skins, morph targets and animations.
#include "layers/models/GltfModel.h"
#include "tests/fuzz/FuzzInput.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    orbis::fuzz::MemoryFile file(data, size);
    if (file.ok()) (void)orbis::models::loadGltf(file.path());
    return 0;
}
