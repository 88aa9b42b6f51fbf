#pragma once
// Decodes a video's frames ahead of playback on a worker: the main thread asks each frame for
// the frame it shows; the frames from there on (in the direction of play) are decoded by one job
// at a time (a VideoFile is not thread-safe) into a small queue. A jump (seek, scrub) cancels
// the job in flight at its next frame and starts from the new place. No Vulkan.
//
//   FramePrefetcher frames(std::move(video), pool);
//   if (const VideoFrame* f = frames.request(index)) upload(*f);   // null: not decoded yet

#include "base/ThreadPool.h"
#include "layers/fmv/VideoFile.h"

#include <deque>
#include <memory>
#include <string>

namespace orbis::fmv {

class FramePrefetcher {
public:
    /// `ahead`: frames decoded beyond the one asked for (the queue holds ahead + 1 and the one
    /// shown).
    FramePrefetcher(std::shared_ptr<VideoFile> video, jobs::ThreadPool& pool, size_t ahead = 4);
    ~FramePrefetcher();
    FramePrefetcher(const FramePrefetcher&) = delete;
    FramePrefetcher& operator=(const FramePrefetcher&) = delete;

    /// Main thread, once a frame: the frame to show now, if decoded (its exact index), else
    /// null; valid until the next call. `backward`: playing in reverse (frames before are
    /// decoded ahead).
    const VideoFrame* request(size_t index, bool backward = false);
    /// True while a decode job runs or is queued.
    bool busy() const { return job_.valid(); }
    /// The first decode error (the video damaged past some point), or empty.
    const std::string& error() const { return error_; }
    size_t framesQueued() const { return frames_.size(); }
    const VideoFile& video() const { return *video_; }

private:
    void collect();
    void schedule(size_t index, bool backward);

    std::shared_ptr<VideoFile> video_;
    jobs::ThreadPool& pool_;
    size_t ahead_;
    std::deque<VideoFrame> frames_;   // decoded, oldest first
    jobs::Job<std::vector<VideoFrame>> job_;
    jobs::CancelToken cancel_;
    size_t jobFirst_ = 0, jobLast_ = 0;   // the job's frames (inclusive), in the order it decodes them
    std::string error_;
};

}  // namespace orbis::fmv
