#include "formats/motion/TrajectoryFile.h"

#include "formats/fmv/KlvFile.h"
#include "formats/motion/TrajectoryGpx.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>

namespace orbis::motion {
namespace {

TrajectoryFormat formatOf(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    if (ext == ".gpx") return TrajectoryFormat::Gpx;
    if (ext == ".csv" || ext == ".txt" || ext == ".tsv") return TrajectoryFormat::Csv;
    if (fmv::looksLikeKlv(path)) return TrajectoryFormat::Klv;
    // By content: XML is GPX, anything else is read as CSV (whose errors then say what is wrong).
    std::ifstream in(path, std::ios::binary);
    char head[256] = {};
    in.read(head, sizeof head);
    for (std::streamsize i = 0; i < in.gcount(); ++i) {
        const unsigned char c = static_cast<unsigned char>(head[i]);
        if (std::isspace(c) || c == 0xEF || c == 0xBB || c == 0xBF) continue;   // blanks, a UTF-8 byte order mark
        return c == '<' ? TrajectoryFormat::Gpx : TrajectoryFormat::Csv;
    }
    return TrajectoryFormat::Csv;
}

}  // namespace

Result<Trajectory> readTrajectory(const std::string& path, const TrajectoryFileOptions& options) {
    const TrajectoryFormat format = options.format == TrajectoryFormat::Auto ? formatOf(path) : options.format;
    std::vector<TrajectorySample> samples;
    switch (format) {
        case TrajectoryFormat::Gpx: {
            auto gpx = readGpx(path);
            if (!gpx) return gpx.error();
            auto s = gpxTrajectorySamples(*gpx, path, options.gpxTrack);
            if (!s) return s.error();
            samples = std::move(*s);
            break;
        }
        case TrajectoryFormat::Klv:
        case TrajectoryFormat::PoseCsv: {
            auto s = format == TrajectoryFormat::Klv ? readKlvSamples(path, options.klv) : readPoseCsvSamples(path);
            if (!s) return s.error();
            samples = std::move(s->samples);
            break;
        }
        case TrajectoryFormat::Auto:
        case TrajectoryFormat::Csv: {
            auto csv = readTrajectoryCsv(path, options.csv);
            if (!csv) return csv.error();
            samples = std::move(csv->samples);
            break;
        }
    }
    return Trajectory::create(std::move(samples), options.trajectory, path);
}

}  // namespace orbis::motion
