#pragma once
// Trajectory samples from MISB ST 0601 metadata (layers/fmv): the platform's pose in each
// packet of a KLV stream (.bin/.klv), or in each row of an FMV pose CSV sidecar. CPU only.
//
// Per packet: time = precision time stamp (tag 2, µs since 1970); position = sensor latitude and
// longitude (tags 13, 14); altitude = the ellipsoid height (tag 104, else 75) as Ellipsoid, else
// the true altitude (tag 15) as MeanSeaLevel; attitude = platform heading (tag 5), pitch (tag 90,
// else 6) and roll (tag 91, else 7), each absent when the packet lacks it (the Trajectory then
// derives it from the motion). The ST 0601 angle convention is Attitude.h's.
//
// Packets are left out, and counted, when they: have no time stamp; have no position or
// height; have a checksum that does not match (unless acceptBadChecksum: a missing checksum is
// accepted); or carry a time not after the last packet kept (encoders repeat packets, and a
// stamp that steps back is a glitch of the stream, not a reason to refuse the whole flight).

#include "base/Result.h"
#include "formats/motion/TrajectorySample.h"

#include <cstddef>
#include <string>
#include <vector>

namespace orbis::fmv {
struct St0601Packet;
}

namespace orbis::motion {

struct KlvSampleOptions {
    bool acceptBadChecksum = false;
};

struct KlvSamples {
    std::vector<TrajectorySample> samples;   ///< in stream order, times increasing
    std::size_t packets = 0;                 ///< packets looked at (decoded ones, for a stream)
    std::size_t undecodable = 0;             ///< packets of a stream that did not decode
    std::size_t withoutTime = 0, withoutPosition = 0, badChecksum = 0, notAfterPrevious = 0;
};

/// The samples of decoded packets (see above). Never fails; an empty result says why in its counts.
/// `lines` (optional, one per packet) become the samples' `line` (for a pose CSV's rows).
KlvSamples samplesFromSt0601(const std::vector<fmv::St0601Packet>& packets, const KlvSampleOptions& options = {},
                             const std::vector<std::size_t>& lines = {});

/// A raw KLV stream (formats/fmv/KlvFile.h's readKlvFile). Errors name the file: unreadable,
/// no ST 0601 key, or no packet that gives a pose (with the counts of why).
Result<KlvSamples> readKlvSamples(const std::string& path, const KlvSampleOptions& options = {});

/// An FMV pose CSV (formats/fmv/PoseCsv.h's readPoseCsv); samples keep the rows' line numbers.
Result<KlvSamples> readPoseCsvSamples(const std::string& path);

}  // namespace orbis::motion
