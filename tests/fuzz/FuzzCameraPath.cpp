// Camera paths (orbis-camera-path JSON): keys, viewpoints, times, interpolation.
#include "engine/scene/CameraPath.h"
#include "tests/fuzz/FuzzInput.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    auto path = orbis::scene::CameraPath::parseText(std::string(orbis::fuzz::text(data, size)), "fuzz.json");
    if (path) {
        const double d = path->duration();
        for (int i = 0; i <= 8; ++i) (void)path->at(path->startTime() + d * i / 8.0);
    }
    return 0;
}
