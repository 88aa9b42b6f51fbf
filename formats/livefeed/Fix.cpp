#include "formats/livefeed/Fix.h"

#include <cmath>
#include <cstdio>

namespace orbis::livefeed {

FeedCounters& FeedCounters::operator+=(const FeedCounters& o) {
    bytes += o.bytes;
    messagesOk += o.messagesOk;
    fixes += o.fixes;
    noFix += o.noFix;
    badChecksum += o.badChecksum;
    unknownType += o.unknownType;
    malformed += o.malformed;
    oversized += o.oversized;
    if (!o.lastError.empty()) lastError = o.lastError;
    return *this;
}

std::string describe(const Fix& fix) {
    char buf[160];
    std::snprintf(buf, sizeof buf, " %.7f%c %.7f%c", std::fabs(fix.latDeg), fix.latDeg < 0 ? 'S' : 'N',
                  std::fabs(fix.lonDeg), fix.lonDeg < 0 ? 'W' : 'E');
    std::string s = formatIso8601(fix.time, 3) + buf;
    auto add = [&](const char* name, const std::optional<double>& v) {
        if (!v) return;
        std::snprintf(buf, sizeof buf, " %s=%.2f", name, *v);
        s += buf;
    };
    add("h", fix.heightEllipsoid);
    add("msl", fix.altitudeMsl);
    add("speed", fix.speedMps);
    add("course", fix.courseDeg);
    add("vspeed", fix.verticalSpeedMps);
    add("heading", fix.headingDeg);
    return s;
}

}  // namespace orbis::livefeed
