#pragma once
// A fixed pool of worker threads running prioritised, cancellable jobs: terrain tiles, file
// reads, decoding. The tile pager re-prioritises queued jobs as the camera moves and cancels the
// ones whose tile went away, so a queued job can be re-ordered (Job::setPriority) or dropped
// (Job::cancel, or its CancelToken) without ever running.
//
//   jobs::CancelToken tileGone = jobs::CancelToken::create();
//   jobs::Job<Heights> job = pool.submit(priority, tileGone, [key](const jobs::CancelToken& cancel) {
//       return readHeights(key, cancel);      // may poll cancel.cancelled() or throwIfCancelled()
//   });
//   ...
//   if (job.ready() && !job.cancelled()) use(job.get());   // main thread, no blocking
//
// Threads are started in the constructor and joined in the destructor; a scene that never asks
// for a pool never starts one (see liveWorkerThreads()). Idle workers sleep on a condition
// variable: nothing spins.

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <type_traits>
#include <utility>
#include <vector>

namespace orbis::jobs {

/// Thrown by Job::get() for a cancelled job. A job's function may throw it too (usually through
/// CancelToken::throwIfCancelled) to stop early; the job then counts as cancelled.
class Cancelled : public std::exception {
public:
    const char* what() const noexcept override { return "job cancelled"; }
};

/// A cheap, copyable handle on a shared cancellation flag. Every method is thread-safe.
class CancelToken {
public:
    /// A token that is never cancelled; cancel() on it does nothing.
    CancelToken() = default;

    /// A fresh token, not yet cancelled.
    static CancelToken create();
    /// A fresh token that also reports cancelled once `parent` is; cancelling the child does not
    /// touch the parent. The pool gives each job such a child of the token it was submitted with,
    /// so that Job::cancel stops one job without cancelling its siblings.
    static CancelToken childOf(const CancelToken& parent);

    void cancel();
    bool cancelled() const;
    /// Throws jobs::Cancelled if cancelled(): the idiomatic early exit inside a job.
    void throwIfCancelled() const;

private:
    struct State {
        std::atomic<bool> flag{false};
        std::shared_ptr<const State> parent;
    };
    explicit CancelToken(std::shared_ptr<State> state) : state_(std::move(state)) {}

    std::shared_ptr<State> state_;
};

class ThreadPool;

namespace detail {

struct Queue;

enum class Status : int { Queued, Running, Succeeded, Failed, Cancelled };

/// The part of a job's shared state that does not depend on its result type.
class JobBase {
public:
    explicit JobBase(CancelToken token) : token_(std::move(token)) {}
    virtual ~JobBase() = default;
    JobBase(const JobBase&) = delete;
    JobBase& operator=(const JobBase&) = delete;

    Status status() const { return status_.load(std::memory_order_acquire); }
    bool finished() const;
    void wait();
    void cancel();
    void setPriority(double priority);
    /// Throws Cancelled or the function's exception; returns if the job succeeded.
    void throwIfUnsuccessful() const;
    /// A queued job whose token was cancelled is taken out of the queue now rather than when a
    /// worker reaches it, so that wait() on it does not wait for a free worker.
    void reapIfTokenCancelled();

protected:
    /// Runs the function on a worker and records the outcome.
    virtual void run() = 0;
    /// Destroys the closure (and what it captured) once it will never run again.
    virtual void releaseFunction() = 0;
    void finish(Status outcome, std::exception_ptr error);
    void finishCancelled();
    void removeFromQueue();

    CancelToken token_;  ///< the job's own child token; set once, never reassigned

private:
    friend class orbis::jobs::ThreadPool;
    friend struct Queue;

    std::atomic<Status> status_{Status::Queued};
    std::exception_ptr error_;
    std::mutex mutex_;
    std::condition_variable done_;

    // Guarded by the pool's queue mutex.
    double priority_ = 0.0;
    std::uint64_t sequence_ = 0;
    bool queued_ = false;
    std::weak_ptr<Queue> queue_;
};

template <typename R>
class JobResult : public JobBase {
public:
    using JobBase::JobBase;
    std::optional<R> value;  ///< set by the worker before the job is marked finished
};

template <>
class JobResult<void> : public JobBase {
public:
    using JobBase::JobBase;
};

template <typename R, typename F>
class JobImpl final : public JobResult<R> {
public:
    template <typename G>
    JobImpl(G&& fn, CancelToken token) : JobResult<R>(std::move(token)), fn_(std::in_place, std::forward<G>(fn)) {}

protected:
    void run() override {
        Status outcome = Status::Succeeded;
        std::exception_ptr error;
        try {
            if constexpr (std::is_void_v<R>)
                std::invoke(*fn_, this->token_);
            else
                this->value.emplace(std::invoke(*fn_, this->token_));
        } catch (const Cancelled&) {
            outcome = Status::Cancelled;
        } catch (...) {
            outcome = Status::Failed;
            error = std::current_exception();
        }
        // Captured resources are released before waiters wake, not when the last handle goes.
        fn_.reset();
        this->finish(outcome, std::move(error));
    }
    void releaseFunction() override { fn_.reset(); }

private:
    std::optional<F> fn_;  // touched only by whoever took the job out of the queue
};

}  // namespace detail

/// A handle on a submitted job. Copies share the job. Every method is thread-safe except get(),
/// which moves the result out and so must be called once, by one thread.
template <typename R>
class Job {
public:
    Job() = default;

    /// False for a default-constructed handle; the other methods need a valid one.
    bool valid() const { return state_ != nullptr; }

    /// True once the job has finished: succeeded, failed or cancelled. Never blocks.
    bool ready() const {
        state_->reapIfTokenCancelled();
        return state_->finished();
    }

    /// True if the job was cancelled before it started, or its function threw jobs::Cancelled.
    bool cancelled() const {
        state_->reapIfTokenCancelled();
        return state_->status() == detail::Status::Cancelled;
    }

    /// Blocks until the job has finished. Do not wait from a worker of the same pool on a job
    /// queued behind it: with every worker waiting, nothing would run it.
    void wait() const { state_->wait(); }

    /// Blocks until finished, then returns the result (moved out: call once). Throws
    /// jobs::Cancelled if the job was cancelled, or rethrows the exception its function threw.
    R get() {
        state_->wait();
        state_->throwIfUnsuccessful();
        if constexpr (!std::is_void_v<R>) {
            if (!state_->value) throw std::logic_error("orbis::jobs::Job::get() called twice");
            R result = std::move(*state_->value);
            state_->value.reset();
            return result;
        }
    }

    /// Cancels this job only: a queued job is dropped and never runs; a running job sees its
    /// token cancelled and may stop early (if it returns normally, its result stands).
    void cancel() { state_->cancel(); }

    /// Moves a still-queued job to its new place in the queue (FIFO position among equal
    /// priorities is kept by submission order). No effect once the job has started.
    void setPriority(double priority) { state_->setPriority(priority); }

private:
    friend class ThreadPool;
    explicit Job(std::shared_ptr<detail::JobResult<R>> state) : state_(std::move(state)) {}

    std::shared_ptr<detail::JobResult<R>> state_;
};

class ThreadPool {
public:
    /// Starts `threads` workers (at least one), named "<name>-<i>" cut to Linux's 15 characters.
    /// Throws std::system_error if a thread cannot be started. Main thread only.
    explicit ThreadPool(unsigned threads, std::string name = "orbis-worker");
    /// Drops every queued job as cancelled (their waiters wake), lets running jobs finish and
    /// joins the workers. Main thread only.
    ~ThreadPool();

    ThreadPool(const ThreadPool&) = delete;
    ThreadPool& operator=(const ThreadPool&) = delete;

    /// Queues fn, a callable R(const CancelToken&). Higher priority runs first; equal priorities
    /// run in submission order; NaN counts as lowest. If `token` is cancelled before a worker
    /// starts the job, fn never runs. Any thread, including workers.
    template <typename F>
    auto submit(double priority, CancelToken token, F&& fn)
        -> Job<std::invoke_result_t<std::decay_t<F>&, const CancelToken&>> {
        using R = std::invoke_result_t<std::decay_t<F>&, const CancelToken&>;
        static_assert(!std::is_reference_v<R>, "a job returns a value, not a reference");
        auto state = std::make_shared<detail::JobImpl<R, std::decay_t<F>>>(std::forward<F>(fn),
                                                                           CancelToken::childOf(token));
        enqueue(state, priority);
        return Job<R>(std::move(state));
    }

    /// Jobs queued and not yet started. Any thread.
    std::size_t pending() const;
    /// Any thread.
    unsigned threadCount() const { return static_cast<unsigned>(workers_.size()); }

    /// Worker threads alive in this process, across all pools. Any thread.
    static int liveWorkerThreads();

private:
    void enqueue(std::shared_ptr<detail::JobBase> job, double priority);
    static void workerLoop(detail::Queue& queue, std::string threadName);

    std::shared_ptr<detail::Queue> queue_;
    std::vector<std::thread> workers_;
};

}  // namespace orbis::jobs
