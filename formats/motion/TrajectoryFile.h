#pragma once
// One call from a file to a Trajectory, whatever the format: a trajectory CSV
// (TrajectoryCsv.h), GPX (TrajectoryGpx.h), a raw KLV stream or an FMV pose CSV
// (TrajectoryKlv.h). CPU only.

#include "base/Result.h"
#include "formats/motion/Trajectory.h"
#include "formats/motion/TrajectoryCsv.h"
#include "formats/motion/TrajectoryKlv.h"

#include <string>

namespace orbis::motion {

enum class TrajectoryFormat {
    Auto,      ///< by extension (.gpx; .bin, .klv; .csv, .txt, .tsv), else by content
    Csv,       ///< TrajectoryCsv.h
    Gpx,       ///< TrajectoryGpx.h
    Klv,       ///< a raw ST 0601 stream
    PoseCsv,   ///< an FMV pose CSV sidecar (formats/fmv/PoseCsv.h)
};

struct TrajectoryFileOptions {
    TrajectoryFormat format = TrajectoryFormat::Auto;
    CsvOptions csv;
    std::string gpxTrack;   ///< see gpxTrajectorySamples(); empty: the first track with times
    KlvSampleOptions klv;
    TrajectoryOptions trajectory;
};

/// Reads `path` and builds its trajectory. Every error names the file. Any thread.
Result<Trajectory> readTrajectory(const std::string& path, const TrajectoryFileOptions& options = {});

}  // namespace orbis::motion
