// An OGC server's GetCapabilities answer (WMS and WFS), as `orbis info URL` reads it.
#include "globe/OgcCapabilities.h"
#include "tests/fuzz/FuzzInput.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string_view text = orbis::fuzz::text(data, size);
    (void)orbis::globe::parseOgcCapabilities(text, orbis::globe::OgcService::Wms, "fuzz");
    (void)orbis::globe::parseOgcCapabilities(text, orbis::globe::OgcService::Wfs, "fuzz");
    (void)orbis::globe::parseOgcCapabilities(text, orbis::globe::OgcService::Wmts, "fuzz");
    return 0;
}
