#pragma once
// The one owner of virtual time (DESIGN.md, "Time, trajectories, models"). The frame loop calls
// advance() once per rendered frame; everything time-dependent (video, trajectories, model
// animation, the sun) observes it and never reads the wall clock.
//
// Time is kept as integer nanoseconds (TimeNs). Playback adds rate * wallSeconds rounded to a
// nanosecond and carries the sub-nanosecond remainder to the next frame, so an hour of 60 Hz
// frames lands on the hour exactly instead of drifting by the accumulated rounding.
//
// Notification happens only in advance(), exactly once per call, never inside seek() and the
// other setters: several seeks within one frame give observers one event, with jumped = true.
//
// Main thread only: nothing here locks.

#include "base/Result.h"
#include "base/TimeFormat.h"

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>

namespace orbis::scene {

/// What observers receive from every advance().
struct TimeEvent {
    TimeNs now = 0;       ///< virtual time after this advance
    TimeNs previous = 0;  ///< `now` of the previous event (for the first event: now before this advance)
    bool playing = false; ///< false once playback stopped at the end of the range
    /// True when time did not move continuously from `previous` to `now`: a seek, step, setRange
    /// or loop wrap happened since the previous event (and on the first event). Observers such
    /// as video players must re-sync instead of interpolating across it.
    bool jumped = false;
    double rate = 1.0;    ///< virtual seconds per wall second
};

namespace detail {
struct TimeObservers;
}

/// Keeps an observer registered; destroying (or reset()) unregisters it. Move-only. Safe to
/// destroy after the TimeServer is gone, and from inside a notification. Main thread only.
class Subscription {
public:
    Subscription() = default;
    Subscription(Subscription&& other) noexcept;
    Subscription& operator=(Subscription&& other) noexcept;
    Subscription(const Subscription&) = delete;
    Subscription& operator=(const Subscription&) = delete;
    ~Subscription();

    /// Unregisters now; the observer is not called again, even later in a notification that is
    /// under way.
    void reset();
    /// True while registered with a TimeServer that still exists.
    bool active() const;

private:
    friend class TimeServer;
    Subscription(std::weak_ptr<detail::TimeObservers> observers, std::uint64_t id)
        : observers_(std::move(observers)), id_(id) {}

    std::weak_ptr<detail::TimeObservers> observers_;
    std::uint64_t id_ = 0;
};

/// Virtual time: a range, a current time, play/pause, rate and loop. Starts paused at 0 with an
/// empty range [0, 0], rate 1, no loop. Main thread only.
class TimeServer {
public:
    TimeServer();
    ~TimeServer();
    TimeServer(const TimeServer&) = delete;
    TimeServer& operator=(const TimeServer&) = delete;

    /// Sets the range and clamps now() into it. Fails, changing nothing, if start > end.
    Result<void> setRange(TimeNs start, TimeNs end);
    TimeNs start() const { return start_; }
    TimeNs end() const { return end_; }
    TimeNs now() const { return now_; }

    void play() { playing_ = true; }
    void pause() { playing_ = false; }
    bool playing() const { return playing_; }

    /// Jumps to t clamped into [start, end]. Observers hear of it at the next advance().
    void seek(TimeNs t);
    /// seek(now() + delta), e.g. one video frame or one minute.
    void step(TimeNs delta);

    /// Virtual seconds per wall second: negative plays backwards, 0 holds. A NaN or infinite
    /// rate is ignored (and logged), so that a bad UI value cannot poison now().
    void setRate(double rate);
    double rate() const { return rate_; }

    /// With loop on, playback past one end of the range continues from the other end.
    void setLoop(bool loop) { loop_ = loop; }
    bool loop() const { return loop_; }

    /// Called once per rendered frame with the wall time since the previous frame (<= 0 or NaN
    /// counts as 0). If playing, moves now() by rate * wallSeconds. Reaching the end (the start
    /// when the rate is negative) wraps when loop is on, else stops there and pauses. Then calls
    /// every observer exactly once. Main thread only, once per frame.
    void advance(double wallSeconds);

    /// Registers an observer, called from advance() until the Subscription is destroyed.
    /// Observers registered during a notification are first called at the next advance().
    /// Main thread only; observers are called on the main thread.
    [[nodiscard]] Subscription observe(std::function<void(const TimeEvent&)> observer);

private:
    /// Moves now_ by delta along the playback direction, applying loop or clamp-and-pause;
    /// returns true if it wrapped around.
    bool moveBy(TimeNs delta);
    void notify(const TimeEvent& event);

    TimeNs start_ = 0;
    TimeNs end_ = 0;
    TimeNs now_ = 0;
    std::optional<TimeNs> reported_;  ///< now_ of the last event
    double rate_ = 1.0;
    double carryNs_ = 0.0;            ///< rounding remainder of the last advance, in [-0.5, 0.5]
    bool playing_ = false;
    bool loop_ = false;
    bool jumpPending_ = true;         ///< the first event has nothing to be continuous with
    std::shared_ptr<detail::TimeObservers> observers_;
};

}  // namespace orbis::scene
