#include "base/ThreadPool.h"

#include <gtest/gtest.h>

#include <pthread.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <future>
#include <limits>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

using namespace orbis::jobs;

namespace {

// Occupies one worker until open(), so that tests can queue jobs behind it and control exactly
// when the queue starts to drain. Declare it after the pool: it opens itself when destroyed,
// before the pool's destructor joins.
class Gate {
public:
    explicit Gate(ThreadPool& pool) {
        std::shared_future<void> opened = open_.get_future().share();
        std::promise<void> started;
        std::future<void> startedFuture = started.get_future();
        job_ = pool.submit(std::numeric_limits<double>::max(), {},
                           [opened, started = std::move(started)](const CancelToken&) mutable {
                               started.set_value();
                               opened.wait();
                           });
        startedFuture.wait();  // the worker is now inside the gate, not merely queued
    }
    ~Gate() { open(); }

    void open() {
        if (!opened_) open_.set_value();
        opened_ = true;
    }
    Job<void>& job() { return job_; }

private:
    std::promise<void> open_;
    bool opened_ = false;
    Job<void> job_;
};

// Records the order in which jobs ran.
struct Order {
    std::mutex mutex;
    std::vector<int> ran;
    void add(int id) {
        std::lock_guard lock(mutex);
        ran.push_back(id);
    }
};

std::string currentThreadName() {
    char name[32] = {};
    pthread_getname_np(pthread_self(), name, sizeof name);
    return name;
}

}  // namespace

TEST(CancelToken, DefaultTokenIsNeverCancelled) {
    CancelToken token;
    token.cancel();
    EXPECT_FALSE(token.cancelled());
    EXPECT_NO_THROW(token.throwIfCancelled());
}

TEST(CancelToken, CopiesShareOneFlag) {
    CancelToken a = CancelToken::create();
    CancelToken b = a;
    EXPECT_FALSE(b.cancelled());
    a.cancel();
    EXPECT_TRUE(b.cancelled());
    EXPECT_THROW(b.throwIfCancelled(), Cancelled);
}

TEST(CancelToken, ChildFollowsParentButNotTheReverse) {
    CancelToken parent = CancelToken::create();
    CancelToken child = CancelToken::childOf(parent);
    child.cancel();
    EXPECT_TRUE(child.cancelled());
    EXPECT_FALSE(parent.cancelled());

    CancelToken child2 = CancelToken::childOf(parent);
    parent.cancel();
    EXPECT_TRUE(child2.cancelled());
}

TEST(ThreadPool, RunsJobAndReturnsItsValue) {
    ThreadPool pool(2);
    Job<int> job = pool.submit(0.0, {}, [](const CancelToken&) { return 6 * 7; });
    EXPECT_EQ(job.get(), 42);
    EXPECT_TRUE(job.ready());
    EXPECT_FALSE(job.cancelled());
}

TEST(ThreadPool, HigherPriorityRunsFirstAndEqualPrioritiesInSubmissionOrder) {
    ThreadPool pool(1);
    Gate gate(pool);
    Order order;
    const double priorities[] = {1, 5, 3, 5, 1, 10};
    std::vector<Job<void>> jobs;
    for (int i = 0; i < 6; ++i)
        jobs.push_back(pool.submit(priorities[i], {}, [&order, i](const CancelToken&) { order.add(i); }));
    EXPECT_EQ(pool.pending(), 6u);
    gate.open();
    for (auto& j : jobs) j.wait();
    EXPECT_EQ(order.ran, (std::vector<int>{5, 1, 3, 2, 0, 4}));
}

TEST(ThreadPool, NanPriorityRunsLast) {
    ThreadPool pool(1);
    Gate gate(pool);
    Order order;
    auto a = pool.submit(std::nan(""), {}, [&](const CancelToken&) { order.add(0); });
    auto b = pool.submit(-1e300, {}, [&](const CancelToken&) { order.add(1); });
    gate.open();
    a.wait();
    b.wait();
    EXPECT_EQ(order.ran, (std::vector<int>{1, 0}));
}

TEST(ThreadPool, TokenCancelledBeforeStartNeverRunsTheFunction) {
    ThreadPool pool(1);
    Gate gate(pool);
    std::atomic<bool> ran{false};
    CancelToken token = CancelToken::create();
    Job<int> job = pool.submit(0.0, token, [&](const CancelToken&) {
        ran = true;
        return 1;
    });
    token.cancel();
    // Reported at once, while the only worker is still busy: the job is reaped from the queue.
    EXPECT_TRUE(job.ready());
    EXPECT_TRUE(job.cancelled());
    EXPECT_EQ(pool.pending(), 0u);
    gate.open();
    EXPECT_THROW(job.get(), Cancelled);
    EXPECT_FALSE(ran);
}

TEST(ThreadPool, TokenCancelledBeforeSubmitIsNeverQueued) {
    ThreadPool pool(1);
    CancelToken token = CancelToken::create();
    token.cancel();
    std::atomic<bool> ran{false};
    Job<void> job = pool.submit(0.0, token, [&](const CancelToken&) { ran = true; });
    EXPECT_EQ(pool.pending(), 0u);
    EXPECT_TRUE(job.cancelled());
    EXPECT_THROW(job.get(), Cancelled);
    EXPECT_FALSE(ran);
}

TEST(ThreadPool, JobCancelDropsQueuedJobWithoutCancellingSiblings) {
    ThreadPool pool(1);
    Gate gate(pool);
    CancelToken shared = CancelToken::create();
    std::atomic<int> ran{0};
    Job<int> dropped = pool.submit(0.0, shared, [&](const CancelToken&) { return ++ran; });
    Job<int> kept = pool.submit(0.0, shared, [&](const CancelToken&) { return ++ran; });
    dropped.cancel();
    EXPECT_EQ(pool.pending(), 1u);
    EXPECT_TRUE(dropped.ready());
    EXPECT_FALSE(shared.cancelled());
    gate.open();
    EXPECT_EQ(kept.get(), 1);
    EXPECT_TRUE(dropped.cancelled());
    EXPECT_EQ(ran.load(), 1);
}

TEST(ThreadPool, CancellingASharedTokenDropsEveryQueuedJobOnIt) {
    ThreadPool pool(1);
    Gate gate(pool);
    CancelToken tile = CancelToken::create();
    std::atomic<int> ran{0};
    std::vector<Job<void>> jobs;
    for (int i = 0; i < 5; ++i) jobs.push_back(pool.submit(0.0, tile, [&](const CancelToken&) { ++ran; }));
    tile.cancel();
    gate.open();
    for (auto& j : jobs) {
        j.wait();
        EXPECT_TRUE(j.cancelled());
    }
    EXPECT_EQ(ran.load(), 0);
}

TEST(ThreadPool, RunningJobSeesJobCancelThroughItsToken) {
    ThreadPool pool(1);
    std::promise<void> started;
    auto startedFuture = started.get_future();
    Job<int> job = pool.submit(0.0, {}, [&](const CancelToken& cancel) {
        started.set_value();
        while (!cancel.cancelled()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
        cancel.throwIfCancelled();
        return 1;
    });
    startedFuture.wait();
    job.cancel();
    job.wait();
    EXPECT_TRUE(job.cancelled());
    EXPECT_THROW(job.get(), Cancelled);
}

TEST(ThreadPool, RunningJobThatIgnoresCancelKeepsItsResult) {
    ThreadPool pool(1);
    std::promise<void> started, cancelled;
    auto startedFuture = started.get_future();
    auto cancelledFuture = cancelled.get_future();
    Job<int> job = pool.submit(0.0, {}, [&](const CancelToken&) {
        started.set_value();
        cancelledFuture.wait();
        return 5;
    });
    startedFuture.wait();
    job.cancel();
    cancelled.set_value();
    EXPECT_EQ(job.get(), 5);
    EXPECT_FALSE(job.cancelled());
}

TEST(ThreadPool, SetPriorityReordersAQueuedJob) {
    ThreadPool pool(1);
    Gate gate(pool);
    Order order;
    auto a = pool.submit(1.0, {}, [&](const CancelToken&) { order.add(0); });
    auto b = pool.submit(2.0, {}, [&](const CancelToken&) { order.add(1); });
    auto c = pool.submit(3.0, {}, [&](const CancelToken&) { order.add(2); });
    a.setPriority(10.0);  // the camera turned towards tile a
    c.setPriority(0.0);   // and away from tile c
    gate.open();
    a.wait();
    b.wait();
    c.wait();
    EXPECT_EQ(order.ran, (std::vector<int>{0, 1, 2}));
}

TEST(ThreadPool, SetPriorityOnFinishedJobHasNoEffect) {
    ThreadPool pool(1);
    Job<int> job = pool.submit(0.0, {}, [](const CancelToken&) { return 3; });
    job.wait();
    job.setPriority(100.0);
    EXPECT_EQ(pool.pending(), 0u);
    EXPECT_EQ(job.get(), 3);
}

TEST(ThreadPool, ExceptionFromTheFunctionIsRethrownByGet) {
    ThreadPool pool(2);
    Job<int> job = pool.submit(0.0, {}, [](const CancelToken&) -> int { throw std::runtime_error("bad tile"); });
    job.wait();
    EXPECT_TRUE(job.ready());
    EXPECT_FALSE(job.cancelled());
    try {
        job.get();
        FAIL() << "get() did not throw";
    } catch (const std::runtime_error& e) {
        EXPECT_STREQ(e.what(), "bad tile");
    }
}

TEST(ThreadPool, MoveOnlyClosureAndResultAreSupported) {
    ThreadPool pool(1);
    auto input = std::make_unique<int>(9);
    Job<std::unique_ptr<int>> job =
        pool.submit(0.0, {}, [p = std::move(input)](const CancelToken&) mutable { return std::move(p); });
    std::unique_ptr<int> out = job.get();
    ASSERT_TRUE(out);
    EXPECT_EQ(*out, 9);
}

TEST(ThreadPool, SecondGetThrowsLogicError) {
    ThreadPool pool(1);
    Job<int> job = pool.submit(0.0, {}, [](const CancelToken&) { return 1; });
    EXPECT_EQ(job.get(), 1);
    EXPECT_THROW(job.get(), std::logic_error);
}

TEST(ThreadPool, ClosureIsReleasedWhenTheJobFinishes) {
    ThreadPool pool(1);
    auto resource = std::make_shared<int>(1);
    std::weak_ptr<int> watch = resource;
    Job<void> job = pool.submit(0.0, {}, [r = std::move(resource)](const CancelToken&) {});
    job.wait();
    // The handle is still alive, but what the closure captured is not.
    EXPECT_TRUE(watch.expired());
}

TEST(ThreadPool, JobMaySubmitAnotherJob) {
    ThreadPool pool(2);
    Job<Job<int>> outer = pool.submit(0.0, {}, [&pool](const CancelToken&) {
        return pool.submit(0.0, {}, [](const CancelToken&) { return 11; });
    });
    EXPECT_EQ(outer.get().get(), 11);
}

TEST(ThreadPool, DestructorDropsQueuedJobsLetsTheRunningOneFinishAndWakesWaiters) {
    std::atomic<int> queuedRan{0};
    Job<int> running;
    std::vector<Job<void>> queued;
    std::future<bool> waiter;
    {
        ThreadPool pool(1);
        // The running job is held until the destructor drops the queued jobs: the first dropped
        // closure opens it from its destructor. This makes the order deterministic.
        auto open = std::make_shared<std::promise<void>>();
        std::shared_future<void> opened = open->get_future().share();
        std::promise<void> started;
        auto startedFuture = started.get_future();
        running = pool.submit(0.0, {}, [opened, started = std::move(started)](const CancelToken&) mutable {
            started.set_value();
            opened.wait();
            return 7;
        });
        startedFuture.wait();
        struct OpenOnDestroy {
            std::shared_ptr<std::promise<void>> open;
            ~OpenOnDestroy() {
                if (open.use_count() == 1) open->set_value();
            }
        };
        for (int i = 0; i < 100; ++i) {
            queued.push_back(pool.submit(0.0, {}, [guard = OpenOnDestroy{open}, &queuedRan](const CancelToken&) {
                ++queuedRan;
            }));
        }
        open.reset();
        Job<void> last = queued.back();
        waiter = std::async(std::launch::async, [last]() mutable {
            last.wait();
            return last.cancelled();
        });
        EXPECT_EQ(pool.pending(), 100u);
    }
    EXPECT_EQ(running.get(), 7);
    EXPECT_EQ(queuedRan.load(), 0);
    for (auto& j : queued) EXPECT_TRUE(j.cancelled());
    EXPECT_TRUE(waiter.get());
}

TEST(ThreadPool, LiveWorkerThreadsCountsStartedAndJoinedWorkers) {
    const int before = ThreadPool::liveWorkerThreads();
    {
        ThreadPool a(3);
        EXPECT_EQ(a.threadCount(), 3u);
        EXPECT_EQ(ThreadPool::liveWorkerThreads(), before + 3);
        ThreadPool b(0);  // asks for none, gets one
        EXPECT_EQ(b.threadCount(), 1u);
        EXPECT_EQ(ThreadPool::liveWorkerThreads(), before + 4);
    }
    EXPECT_EQ(ThreadPool::liveWorkerThreads(), before);
}

TEST(ThreadPool, WorkerThreadsAreNamedWithinFifteenCharacters) {
    {
        ThreadPool pool(1);
        EXPECT_EQ(pool.submit(0.0, {}, [](const CancelToken&) { return currentThreadName(); }).get(), "orbis-worker-0");
    }
    ThreadPool pool(1, "a-very-long-pool-name");
    const std::string name = pool.submit(0.0, {}, [](const CancelToken&) { return currentThreadName(); }).get();
    EXPECT_EQ(name, "a-very-long-p-0");
}

TEST(ThreadPool, StressEveryJobRunsOnceOrIsCancelled) {
    constexpr int kSubmitters = 4;
    constexpr int kPerSubmitter = 5000;
    constexpr int kTotal = kSubmitters * kPerSubmitter;
    std::vector<std::atomic<int>> runs(kTotal);
    std::vector<Job<int>> jobs(kTotal);
    std::atomic<long long> sum{0};
    {
        ThreadPool pool(4);
        std::vector<std::thread> submitters;
        for (int s = 0; s < kSubmitters; ++s) {
            submitters.emplace_back([&, s] {
                CancelToken group = CancelToken::create();
                for (int i = 0; i < kPerSubmitter; ++i) {
                    const int id = s * kPerSubmitter + i;
                    jobs[id] = pool.submit(id % 13, group, [&, id](const CancelToken&) {
                        runs[id].fetch_add(1);
                        sum += id;
                        return id;
                    });
                    if (id % 7 == 0) jobs[id].cancel();
                    if (id % 5 == 0) jobs[id].setPriority(-id);
                    if (i == kPerSubmitter / 2 && s == 0) group.cancel();  // a whole tile goes away
                }
            });
        }
        for (auto& t : submitters) t.join();
        for (auto& j : jobs) j.wait();
    }
    long long expectedSum = 0;
    int ran = 0, cancelled = 0;
    for (int id = 0; id < kTotal; ++id) {
        ASSERT_TRUE(jobs[id].ready()) << id;
        if (jobs[id].cancelled()) {
            ASSERT_EQ(runs[id].load(), 0) << id;
            ++cancelled;
        } else {
            ASSERT_EQ(runs[id].load(), 1) << id;
            ASSERT_EQ(jobs[id].get(), id);
            expectedSum += id;
            ++ran;
        }
    }
    EXPECT_EQ(ran + cancelled, kTotal);
    EXPECT_GT(ran, kTotal / 2);
    EXPECT_EQ(sum.load(), expectedSum);
}
