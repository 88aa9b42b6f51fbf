#pragma once
// A scripted camera path: viewpoints at given times, played back by interpolating between them
// with globe::interpolateFlight (great-circle target motion, heading the short way, range
// arcing up on long legs). No Vulkan.
//
// File format (JSON):
//
// {
//   "orbis-camera-path": 1,
//   "interpolation": "smooth",          // optional: "smooth" (default) or "linear"
//   "keys": [
//     {"t": 0,  "viewpoint": {"lon": 10, "lat": 45, "height": 0, "heading": 0, "pitch": -90, "range": 2e7}},
//     {"t": 12, "viewpoint": {"lon": 11, "lat": 46, "range": 5000, "pitch": -30}}
//   ]
// }
//
// t is in seconds from the start of playback, >= 0 and strictly increasing; at least two keys.
// The viewpoint objects are those of scene files (readViewpoint: every field optional, with the
// same defaults). "smooth" eases in and out of every key (the camera pauses on each key);
// "linear" moves at constant parameter speed and turns sharply at keys. Unknown keys anywhere
// are errors.

#include "base/Result.h"
#include "globe/Viewpoint.h"

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace orbis::scene {

class CameraPath {
public:
    enum class Interpolation { Smooth, Linear };

    struct Key {
        double t = 0.0;   ///< seconds
        globe::Viewpoint viewpoint;
    };

    /// Never throws: a missing, oversized or malformed file gives an Error naming the file and
    /// the JSON path of the problem. Any thread.
    static Result<CameraPath> parseFile(const std::filesystem::path& file);
    /// `fileNameForErrors` starts every error message ("<memory>" when empty).
    static Result<CameraPath> parseText(std::string text, std::string fileNameForErrors);

    /// The viewpoint at `seconds`: the first key's before the start, the last key's after the
    /// end, exactly a key's at its time.
    globe::Viewpoint at(double seconds) const;

    double startTime() const { return keys_.empty() ? 0.0 : keys_.front().t; }
    double endTime() const { return keys_.empty() ? 0.0 : keys_.back().t; }
    /// endTime() - startTime().
    double duration() const { return endTime() - startTime(); }
    size_t size() const { return keys_.size(); }
    const std::vector<Key>& keys() const { return keys_; }
    Interpolation interpolation() const { return interpolation_; }

private:
    std::vector<Key> keys_;
    Interpolation interpolation_ = Interpolation::Smooth;
};

/// Largest camera path file accepted (a path is a list of viewpoints, not data).
constexpr std::uintmax_t kMaxCameraPathFileBytes = 16u << 20;

}  // namespace orbis::scene
