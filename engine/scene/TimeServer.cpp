#include "engine/scene/TimeServer.h"

#include "base/Log.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <utility>
#include <vector>

namespace orbis::scene {

// The observer list lives apart from the TimeServer, shared with the Subscriptions through weak
// pointers, so that a Subscription can outlive its server.
namespace detail {

struct TimeObservers {
    struct Entry {
        std::uint64_t id = 0;
        std::function<void(const TimeEvent&)> fn;
        bool active = true;
    };

    // shared_ptr entries: a notification holds the one it is calling, so the vector may grow
    // (an observer subscribing another) without moving the function that is running.
    std::vector<std::shared_ptr<Entry>> entries;
    std::uint64_t nextId = 1;
    int notifying = 0;  // depth: advance() may be re-entered from an observer
    bool needsCompaction = false;

    void remove(std::uint64_t id) {
        for (auto& e : entries) {
            if (e->id != id || !e->active) continue;
            e->active = false;
            needsCompaction = true;
            break;
        }
        if (notifying == 0) compact();
    }

    // Drops inactive entries. The functions are destroyed after the vector is consistent again,
    // because destroying a closure may destroy another Subscription and re-enter remove().
    void compact() {
        if (!needsCompaction) return;
        needsCompaction = false;
        std::vector<std::shared_ptr<Entry>> doomed;
        auto keep = std::stable_partition(entries.begin(), entries.end(), [](const auto& e) { return e->active; });
        std::move(keep, entries.end(), std::back_inserter(doomed));
        entries.erase(keep, entries.end());
    }
};

}  // namespace detail

namespace {

constexpr TimeNs kMaxTime = std::numeric_limits<TimeNs>::max();
constexpr TimeNs kMinTime = std::numeric_limits<TimeNs>::min();

TimeNs saturatingAdd(TimeNs a, TimeNs b) {
    TimeNs sum = 0;
    if (__builtin_add_overflow(a, b, &sum)) return b > 0 ? kMaxTime : kMinTime;
    return sum;
}

// Differences of two TimeNs can exceed int64 (the range may span the whole int64), so the loop
// arithmetic is done in uint64, where wrap-around subtraction is exact for a >= b.
std::uint64_t distance(TimeNs from, TimeNs to) {
    return static_cast<std::uint64_t>(to) - static_cast<std::uint64_t>(from);
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Subscription

Subscription::Subscription(Subscription&& other) noexcept
    : observers_(std::move(other.observers_)), id_(std::exchange(other.id_, 0)) {}

Subscription& Subscription::operator=(Subscription&& other) noexcept {
    if (this != &other) {
        reset();
        observers_ = std::move(other.observers_);
        id_ = std::exchange(other.id_, 0);
    }
    return *this;
}

Subscription::~Subscription() { reset(); }

void Subscription::reset() {
    if (auto observers = observers_.lock()) observers->remove(id_);
    observers_.reset();
    id_ = 0;
}

bool Subscription::active() const { return id_ != 0 && !observers_.expired(); }

// ---------------------------------------------------------------------------------------------
// TimeServer

TimeServer::TimeServer() : observers_(std::make_shared<detail::TimeObservers>()) {}

TimeServer::~TimeServer() = default;

Result<void> TimeServer::setRange(TimeNs start, TimeNs end) {
    if (start > end)
        return makeError("time range start " + formatIso8601(start) + " is after its end " + formatIso8601(end));
    start_ = start;
    end_ = end;
    now_ = std::clamp(now_, start_, end_);
    carryNs_ = 0.0;
    jumpPending_ = true;
    return {};
}

void TimeServer::seek(TimeNs t) {
    now_ = std::clamp(t, start_, end_);
    carryNs_ = 0.0;
    jumpPending_ = true;
}

void TimeServer::step(TimeNs delta) { seek(saturatingAdd(now_, delta)); }

void TimeServer::setRate(double rate) {
    if (!std::isfinite(rate)) {
        log::warn("time: ignoring non-finite playback rate ", rate);
        return;
    }
    rate_ = rate;
    carryNs_ = 0.0;
}

bool TimeServer::moveBy(TimeNs delta) {
    const TimeNs next = saturatingAdd(now_, delta);
    const std::uint64_t span = distance(start_, end_);
    if (delta > 0 && next >= end_) {
        if (loop_ && span > 0 && next > end_) {
            // Keep the overshoot so that a loop plays at a constant rate across the seam.
            now_ = static_cast<TimeNs>(static_cast<std::uint64_t>(start_) + distance(end_, next) % span);
            return true;
        }
        now_ = end_;
        if (!loop_) playing_ = false;
        return false;
    }
    if (delta < 0 && next <= start_) {
        if (loop_ && span > 0 && next < start_) {
            now_ = static_cast<TimeNs>(static_cast<std::uint64_t>(end_) - distance(next, start_) % span);
            return true;
        }
        now_ = start_;
        if (!loop_) playing_ = false;
        return false;
    }
    now_ = next;
    return false;
}

void TimeServer::advance(double wallSeconds) {
    const TimeNs before = now_;
    bool wrapped = false;
    if (playing_ && wallSeconds > 0.0 && std::isfinite(wallSeconds) && rate_ != 0.0) {
        const double exactNs = rate_ * wallSeconds * 1e9 + carryNs_;
        TimeNs delta = 0;
        // 9e18 ns is within the int64 range with margin for llround; beyond it, saturate.
        if (std::fabs(exactNs) < 9e18) {
            delta = static_cast<TimeNs>(std::llround(exactNs));
            carryNs_ = exactNs - static_cast<double>(delta);
        } else {
            delta = exactNs > 0 ? kMaxTime : kMinTime;
            carryNs_ = 0.0;
        }
        wrapped = moveBy(delta);
        if (!playing_) carryNs_ = 0.0;  // stopped at an end: the remainder has nowhere to go
    }

    TimeEvent event;
    event.now = now_;
    event.previous = reported_.value_or(before);
    event.playing = playing_;
    event.jumped = jumpPending_ || wrapped;
    event.rate = rate_;
    jumpPending_ = false;
    reported_ = now_;
    notify(event);
}

Subscription TimeServer::observe(std::function<void(const TimeEvent&)> observer) {
    if (!observer) return {};
    auto entry = std::make_shared<detail::TimeObservers::Entry>();
    entry->id = observers_->nextId++;
    entry->fn = std::move(observer);
    observers_->entries.push_back(entry);
    return Subscription(observers_, entry->id);
}

void TimeServer::notify(const TimeEvent& event) {
    // Held locally: an observer might even destroy this TimeServer.
    const std::shared_ptr<detail::TimeObservers> observers = observers_;
    struct Depth {
        detail::TimeObservers& o;
        explicit Depth(detail::TimeObservers& obs) : o(obs) { ++o.notifying; }
        ~Depth() {
            if (--o.notifying == 0) o.compact();
        }
    } depth(*observers);

    // Only those registered before this notification: ones added by an observer wait for the next.
    const std::size_t count = observers->entries.size();
    for (std::size_t i = 0; i < count; ++i) {
        const std::shared_ptr<detail::TimeObservers::Entry> entry = observers->entries[i];
        if (entry->active) entry->fn(event);
    }
}

}  // namespace orbis::scene
