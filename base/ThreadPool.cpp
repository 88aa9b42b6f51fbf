#include "base/ThreadPool.h"

#include "base/Log.h"

#include <pthread.h>

#include <cmath>
#include <limits>
#include <set>

namespace orbis::jobs {

// ---------------------------------------------------------------------------------------------
// CancelToken

CancelToken CancelToken::create() { return CancelToken(std::make_shared<State>()); }

CancelToken CancelToken::childOf(const CancelToken& parent) {
    auto state = std::make_shared<State>();
    state->parent = parent.state_;
    return CancelToken(std::move(state));
}

void CancelToken::cancel() {
    if (state_) state_->flag.store(true, std::memory_order_release);
}

bool CancelToken::cancelled() const {
    // A chain is at most a few links long: a job's own token, the caller's, its parent.
    for (const State* s = state_.get(); s; s = s->parent.get())
        if (s->flag.load(std::memory_order_acquire)) return true;
    return false;
}

void CancelToken::throwIfCancelled() const {
    if (cancelled()) throw Cancelled();
}

// ---------------------------------------------------------------------------------------------
// The queue shared by the pool, its workers and the job handles. Handles hold it weakly: a
// handle may outlive the pool.

namespace detail {

struct Queue {
    // Highest priority first, then submission order. Transparent, so that a job can find itself
    // by raw pointer without a shared_ptr to itself.
    struct Before {
        using is_transparent = void;
        static bool less(const JobBase* a, const JobBase* b) {
            if (a->priority_ != b->priority_) return a->priority_ > b->priority_;
            return a->sequence_ < b->sequence_;
        }
        bool operator()(const std::shared_ptr<JobBase>& a, const std::shared_ptr<JobBase>& b) const {
            return less(a.get(), b.get());
        }
        bool operator()(const std::shared_ptr<JobBase>& a, const JobBase* b) const { return less(a.get(), b); }
        bool operator()(const JobBase* a, const std::shared_ptr<JobBase>& b) const { return less(a, b.get()); }
    };

    mutable std::mutex mutex;
    std::condition_variable wake;
    std::set<std::shared_ptr<JobBase>, Before> jobs;
    std::uint64_t nextSequence = 0;
    bool stopping = false;
};

namespace {

// NaN would break the strict weak ordering of the queue.
double sanitize(double priority) { return std::isnan(priority) ? -std::numeric_limits<double>::infinity() : priority; }

bool isFinal(Status s) { return s == Status::Succeeded || s == Status::Failed || s == Status::Cancelled; }

}  // namespace

bool JobBase::finished() const { return isFinal(status()); }

void JobBase::wait() {
    reapIfTokenCancelled();
    std::unique_lock lock(mutex_);
    done_.wait(lock, [this] { return finished(); });
}

void JobBase::throwIfUnsuccessful() const {
    switch (status()) {
        case Status::Cancelled: throw Cancelled();
        case Status::Failed: std::rethrow_exception(error_);
        default: return;
    }
}

void JobBase::finish(Status outcome, std::exception_ptr error) {
    {
        std::lock_guard lock(mutex_);
        error_ = std::move(error);
        status_.store(outcome, std::memory_order_release);
    }
    done_.notify_all();
}

void JobBase::finishCancelled() {
    releaseFunction();
    finish(Status::Cancelled, nullptr);
}

void JobBase::removeFromQueue() {
    const std::shared_ptr<Queue> queue = queue_.lock();
    if (!queue) return;  // the pool is gone; its destructor already finished every queued job
    bool removed = false;
    {
        std::lock_guard lock(queue->mutex);
        if (queued_) {
            queue->jobs.erase(queue->jobs.find(this));
            queued_ = false;
            removed = true;
        }
    }
    // Outside the lock: the closure's destructor may do anything, even submit another job.
    if (removed) finishCancelled();
}

void JobBase::cancel() {
    token_.cancel();  // the job's own child token: a running function sees it
    removeFromQueue();
}

void JobBase::reapIfTokenCancelled() {
    if (status() == Status::Queued && token_.cancelled()) removeFromQueue();
}

void JobBase::setPriority(double priority) {
    priority = sanitize(priority);
    const std::shared_ptr<Queue> queue = queue_.lock();
    if (!queue) return;
    std::lock_guard lock(queue->mutex);
    if (!queued_) return;
    // The set orders by priority, so the job leaves and re-enters rather than being edited in place.
    auto node = queue->jobs.extract(queue->jobs.find(this));
    priority_ = priority;
    queue->jobs.insert(std::move(node));
}

}  // namespace detail

// ---------------------------------------------------------------------------------------------
// ThreadPool

namespace {

std::atomic<int> gLiveWorkers{0};

// Linux limits thread names to 15 characters; keep the index, shorten the base.
std::string threadName(const std::string& base, unsigned index) {
    constexpr std::size_t kMaxName = 15;
    std::string suffix(1, '-');
    suffix += std::to_string(index);
    const std::size_t room = suffix.size() < kMaxName ? kMaxName - suffix.size() : 0;
    return (base.substr(0, room) + suffix).substr(0, kMaxName);
}

}  // namespace

ThreadPool::ThreadPool(unsigned threads, std::string name) : queue_(std::make_shared<detail::Queue>()) {
    if (threads == 0) threads = 1;
    workers_.reserve(threads);
    try {
        for (unsigned i = 0; i < threads; ++i) {
            // Counted here rather than in the thread, so the count is exact when we return.
            gLiveWorkers.fetch_add(1);
            try {
                workers_.emplace_back(&ThreadPool::workerLoop, std::ref(*queue_), threadName(name, i));
            } catch (...) {
                gLiveWorkers.fetch_sub(1);
                throw;
            }
        }
    } catch (...) {
        {
            std::lock_guard lock(queue_->mutex);
            queue_->stopping = true;
        }
        queue_->wake.notify_all();
        for (auto& t : workers_) t.join();
        throw;
    }
}

ThreadPool::~ThreadPool() {
    std::vector<std::shared_ptr<detail::JobBase>> dropped;
    {
        std::lock_guard lock(queue_->mutex);
        queue_->stopping = true;
        dropped.reserve(queue_->jobs.size());
        for (const auto& job : queue_->jobs) {
            job->queued_ = false;
            dropped.push_back(job);
        }
        queue_->jobs.clear();
    }
    queue_->wake.notify_all();
    // Before joining: a running job may be waiting on one of these, and would otherwise never end.
    for (auto& job : dropped) job->finishCancelled();
    if (!dropped.empty()) log::debug("thread pool: dropped ", dropped.size(), " queued jobs at shutdown");
    for (auto& t : workers_) t.join();
}

void ThreadPool::enqueue(std::shared_ptr<detail::JobBase> job, double priority) {
    bool accepted = false;
    if (!job->token_.cancelled()) {
        std::lock_guard lock(queue_->mutex);
        if (!queue_->stopping) {
            job->priority_ = detail::sanitize(priority);
            job->sequence_ = queue_->nextSequence++;
            job->queued_ = true;
            job->queue_ = queue_;
            queue_->jobs.insert(job);
            accepted = true;
        }
    }
    if (accepted)
        queue_->wake.notify_one();
    else
        job->finishCancelled();  // already cancelled, or submitted from a job while shutting down
}

std::size_t ThreadPool::pending() const {
    std::lock_guard lock(queue_->mutex);
    return queue_->jobs.size();
}

int ThreadPool::liveWorkerThreads() { return gLiveWorkers.load(); }

void ThreadPool::workerLoop(detail::Queue& queue, std::string name) {
    pthread_setname_np(pthread_self(), name.c_str());
    for (;;) {
        std::shared_ptr<detail::JobBase> job;
        {
            std::unique_lock lock(queue.mutex);
            queue.wake.wait(lock, [&] { return queue.stopping || !queue.jobs.empty(); });
            if (queue.stopping) break;  // the destructor finishes whatever is still queued
            job = std::move(queue.jobs.extract(queue.jobs.begin()).value());
            job->queued_ = false;
        }
        if (job->token_.cancelled()) {
            job->finishCancelled();
            continue;
        }
        job->status_.store(detail::Status::Running, std::memory_order_release);
        job->run();
    }
    gLiveWorkers.fetch_sub(1);
}

}  // namespace orbis::jobs
