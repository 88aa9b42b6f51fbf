// A WMS TIME extent, from a scene file or a server's capabilities (globe/WmsTime.h).
#include "globe/WmsTime.h"
#include "tests/fuzz/FuzzInput.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const auto values = orbis::globe::parseWmsTimeExtent(orbis::fuzz::text(data, size));
    if (values && !values->empty()) (void)orbis::globe::wmsTimeIndexAt(*values, 0);
    return 0;
}
