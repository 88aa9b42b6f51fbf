#include "layers/fmv/FramePrefetcher.h"

#include <algorithm>

namespace orbis::fmv {

FramePrefetcher::FramePrefetcher(std::shared_ptr<VideoFile> video, jobs::ThreadPool& pool, size_t ahead)
    : video_(std::move(video)), pool_(pool), ahead_(std::max<size_t>(ahead, 1)) {}

FramePrefetcher::~FramePrefetcher() {
    if (job_.valid()) {
        cancel_.cancel();
        job_.wait();   // the job uses video_: let it stop at its next frame
    }
}

void FramePrefetcher::collect() {
    if (!job_.valid() || !job_.ready()) return;
    auto job = std::move(job_);
    job_ = {};
    try {
        for (VideoFrame& f : job.get()) frames_.push_back(std::move(f));
    } catch (const jobs::Cancelled&) {
    } catch (const std::exception& e) {
        if (error_.empty()) error_ = e.what();
    }
}

void FramePrefetcher::schedule(size_t index, bool backward) {
    const size_t count = video_->frameCount();
    size_t first = index, last = index;
    if (backward) first = index >= ahead_ ? index - ahead_ : 0;
    else last = std::min(index + ahead_, count - 1);
    // Only the frames not queued already.
    std::vector<size_t> missing;
    for (size_t k = first; k <= last; ++k)
        if (std::none_of(frames_.begin(), frames_.end(), [&](const VideoFrame& f) { return f.index == k; })) missing.push_back(k);
    if (missing.empty()) return;
    cancel_ = jobs::CancelToken::create();
    jobFirst_ = missing.front();
    jobLast_ = missing.back();
    std::shared_ptr<VideoFile> video = video_;
    job_ = pool_.submit(1.0, cancel_, [video, missing](const jobs::CancelToken& cancel) {
        std::vector<VideoFrame> out;
        for (size_t k : missing) {   // increasing: the decoder runs forward even when playing back
            if (cancel.cancelled()) break;
            auto f = video->decode(k);
            if (!f) throw std::runtime_error(f.message());
            out.push_back(std::move(*f));
        }
        return out;
    });
}

const VideoFrame* FramePrefetcher::request(size_t index, bool backward) {
    if (video_->frameCount() == 0) return nullptr;
    index = std::min(index, video_->frameCount() - 1);
    collect();
    // A job that does not cover the frame asked for is stale: stop it (its frames so far are
    // kept when it returns).
    if (job_.valid() && (index < jobFirst_ || index > jobLast_)) cancel_.cancel();
    // Frames behind the play direction (and beyond the window) go.
    const auto inWindow = [&](size_t k) {
        return backward ? (k <= index && k + ahead_ >= index) : (k >= index && k <= index + ahead_);
    };
    std::erase_if(frames_, [&](const VideoFrame& f) { return !inWindow(f.index); });
    if (!job_.valid() && error_.empty()) schedule(index, backward);
    for (const VideoFrame& f : frames_)
        if (f.index == index) return &f;
    return nullptr;
}

}  // namespace orbis::fmv
