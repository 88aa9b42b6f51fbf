// GPX: the XML scanner (entities, comments, CDATA, namespaces) and the tracks, routes and
// waypoints it builds; then the samples of the first timed track.
#include "formats/motion/TrajectoryGpx.h"
#include "tests/fuzz/FuzzInput.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    auto gpx = orbis::motion::parseGpx(orbis::fuzz::text(data, size), "fuzz.gpx");
    if (gpx) (void)orbis::motion::gpxTrajectorySamples(*gpx, "fuzz.gpx");
    return 0;
}
