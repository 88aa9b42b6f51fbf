#include "formats/motion/TrajectoryKlv.h"

#include "formats/fmv/KlvFile.h"
#include "formats/fmv/PoseCsv.h"
#include "formats/fmv/St0601.h"

#include <cstdint>

namespace orbis::motion {
namespace {

Result<KlvSamples> notEmpty(KlvSamples s, const std::string& path) {
    if (!s.samples.empty()) return s;
    std::string why = std::to_string(s.withoutTime) + " without a time stamp (tag 2), " + std::to_string(s.withoutPosition) +
                      " without a position or height (tags 13, 14; 15, 75 or 104), " + std::to_string(s.badChecksum) +
                      " with a bad checksum";
    if (s.undecodable > 0) why += ", " + std::to_string(s.undecodable) + " that do not decode";
    return makeError(path + ": none of the " + std::to_string(s.packets + s.undecodable) + " packets gives a platform pose (" + why + ")");
}

}  // namespace

KlvSamples samplesFromSt0601(const std::vector<fmv::St0601Packet>& packets, const KlvSampleOptions& options,
                             const std::vector<std::size_t>& lines) {
    KlvSamples out;
    out.packets = packets.size();
    for (std::size_t i = 0; i < packets.size(); ++i) {
        const fmv::St0601Packet& p = packets[i];
        if (p.checksum == fmv::ChecksumVerdict::Mismatch && !options.acceptBadChecksum) {
            ++out.badChecksum;
            continue;
        }
        if (!p.precisionTimeUs) {
            ++out.withoutTime;
            continue;
        }
        const auto hae = p.sensorHeightAboveEllipsoid();
        if (!p.sensorLatitudeDeg || !p.sensorLongitudeDeg || (!hae && !p.sensorTrueAltitude)) {
            ++out.withoutPosition;
            continue;
        }
        // ST 0601 tag 2: uint64 µs since 1970; int64 ns holds it up to 2262.
        if (*p.precisionTimeUs > uint64_t(INT64_MAX / 1000)) {
            ++out.withoutTime;
            continue;
        }
        TrajectorySample s;
        s.t = TimeNs(*p.precisionTimeUs) * 1000;
        if (!out.samples.empty() && s.t <= out.samples.back().t) {
            ++out.notAfterPrevious;
            continue;
        }
        s.latDeg = *p.sensorLatitudeDeg;
        s.lonDeg = *p.sensorLongitudeDeg;
        s.alt = hae ? *hae : *p.sensorTrueAltitude;
        s.altRef = hae ? AltitudeRef::Ellipsoid : AltitudeRef::MeanSeaLevel;
        s.headingDeg = p.platformHeadingDeg;
        s.pitchDeg = p.pitchDeg();
        s.rollDeg = p.rollDeg();
        s.line = i < lines.size() ? lines[i] : 0;
        out.samples.push_back(s);
    }
    return out;
}

Result<KlvSamples> readKlvSamples(const std::string& path, const KlvSampleOptions& options) {
    auto stream = fmv::readKlvFile(path);
    if (!stream) return stream.error();
    std::vector<fmv::St0601Packet> packets;
    packets.reserve(stream->records.size());
    std::size_t undecodable = 0;
    for (fmv::KlvRecord& r : stream->records) {
        if (r.packet) packets.push_back(std::move(*r.packet));
        else ++undecodable;
    }
    KlvSamples s = samplesFromSt0601(packets, options);
    s.undecodable = undecodable;
    return notEmpty(std::move(s), path);
}

Result<KlvSamples> readPoseCsvSamples(const std::string& path) {
    auto csv = fmv::readPoseCsv(path);
    if (!csv) return csv.error();
    std::vector<fmv::St0601Packet> packets;
    std::vector<std::size_t> lines;
    packets.reserve(csv->samples.size());
    lines.reserve(csv->samples.size());
    for (fmv::PoseSample& row : csv->samples) {
        packets.push_back(std::move(row.pose));
        lines.push_back(row.line);
    }
    return notEmpty(samplesFromSt0601(packets, {}, lines), path);
}

}  // namespace orbis::motion
