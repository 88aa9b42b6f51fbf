#pragma once
// A live position source: a background thread that connects to a TCP server (or binds a UDP
// port), decodes NMEA 0183 or XML position messages as they arrive, and queues the Fixes for
// the main thread, which takes them with drain() once per frame.
//
//   auto src = LiveSource::open("tcp://192.168.1.20:10110");
//   if (!src) { log::error(src.message()); return; }
//   for (const Fix& f : (*src)->drain()) model.moveTo(f);   // each frame
//
// Connection: TCP connects (names through getaddrinfo, IPv4 and IPv6, each address in turn);
// UDP binds host:port and takes every datagram (one or more lines or messages; a datagram is
// complete in itself). When the server closes, refuses, cannot be resolved or errs, the thread
// waits and tries again: the wait starts at reconnectMin and doubles up to reconnectMax after
// each failure, and falls back to reconnectMin once a connection has delivered data. While it
// waits it sleeps in poll(): no busy loop whatever the network does.
//
// Stopping: stop() (or the destructor) wakes the thread through an eventfd and joins it; this
// takes well under 100 ms whether the thread is connecting, waiting to reconnect or reading a
// silent server. The exception is a host-name lookup in progress (getaddrinfo cannot be
// interrupted): stop() then waits for the resolver. Numeric addresses never wait.
//
// Queue: at most queueCapacity fixes; when the consumer is slow the oldest are dropped and
// counted (LiveStats::dropped; Fix::sequence shows the gap). latest() is kept apart from the
// queue, so a display of the current position never misses it.
//
// Threads: open() on any thread; drain(), latest(), stats(), waitForFixes() and stop() are
// thread-safe. Nothing thrown escapes the reader thread (an unexpected exception stops it and
// shows in stats().lastError).

#include "base/Result.h"
#include "formats/livefeed/FeedAddress.h"
#include "formats/livefeed/Fix.h"
#include "formats/livefeed/FixDecoder.h"

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <string_view>
#include <thread>
#include <vector>

namespace orbis::livefeed {

class WakeFd;

struct LiveSourceOptions {
    FeedProtocol protocol = FeedProtocol::Auto;   ///< Auto: '$' NMEA, '<' XML, per connection
    bool requireChecksum = true;                  ///< NMEA: drop sentences without "*hh"
    /// The date for NMEA GGA times until the first RMC (GGA has none); default: the system
    /// clock when open() is called.
    std::optional<TimeNs> referenceTime;
    std::chrono::milliseconds reconnectMin{100};
    std::chrono::milliseconds reconnectMax{2000};
    std::chrono::milliseconds connectTimeout{2000};
    /// After this much silence an NMEA fix held back for the rest of its epoch is emitted
    /// (NmeaDecoder.h: only when a sentence the receiver usually sends went missing).
    std::chrono::milliseconds flushAfterSilence{200};
    std::size_t queueCapacity = 1024;             ///< fixes kept for drain(); oldest dropped beyond
};

struct LiveStats {
    std::string address;              ///< as given to open()
    bool connected = false;           ///< TCP: connected; UDP: bound
    FeedProtocol protocol = FeedProtocol::Auto;   ///< what the current (or last) connection speaks
    std::uint16_t localPort = 0;      ///< UDP: the bound port (useful with port 0)
    std::uint64_t connectAttempts = 0;
    std::uint64_t connections = 0;    ///< successful connects (UDP: binds)
    std::uint64_t reconnects = 0;     ///< connections after the first one
    std::uint64_t disconnects = 0;    ///< connections lost (server closed, read error)
    std::uint64_t fixesReceived = 0;  ///< fixes decoded over the source's life
    std::uint64_t dropped = 0;        ///< fixes dropped because the queue was full
    std::size_t queued = 0;           ///< fixes waiting for drain()
    std::size_t maxBufferedBytes = 0; ///< the decoder's largest partial line/message (bounded)
    FeedCounters decoded;             ///< what the decoder saw (checksums, malformed, ...)
    std::string lastError;            ///< last connection problem, naming the feed and address
};

class LiveSource {
public:
    using Clock = std::chrono::steady_clock;

    /// Parses `url` (FeedAddress.h) and starts the reader thread. Fails only on a bad address
    /// or when no thread can be started; an unreachable server is not an error (it is retried).
    static Result<std::unique_ptr<LiveSource>> open(std::string_view url, LiveSourceOptions options = {});

    ~LiveSource();
    LiveSource(const LiveSource&) = delete;
    LiveSource& operator=(const LiveSource&) = delete;

    /// Stops and joins the reader thread; idempotent. Any thread but the reader.
    void stop();

    /// The fixes received since the last call, oldest first. Any thread.
    std::vector<Fix> drain();
    /// The most recent fix, drained or not. Any thread.
    std::optional<Fix> latest() const;
    /// A snapshot of the counters. Any thread.
    LiveStats stats() const;
    /// Waits until a fix is queued (true), `timeout` passes or the source stops (false). Any thread.
    bool waitForFixes(std::chrono::milliseconds timeout) const;

    const FeedAddress& address() const { return address_; }

private:
    LiveSource(FeedAddress address, LiveSourceOptions options);

    void run();                                      // the reader thread
    void loop();
    /// Reads one connection until it ends; returns why it ended ("" when stopped). `gotData`:
    /// whether any byte came.
    std::string readConnection(int fd, FixDecoder& decoder, bool& gotData);
    void publish(std::vector<Fix>& fixes, const FixDecoder& decoder);
    void setError(std::string message);

    FeedAddress address_;
    LiveSourceOptions options_;
    std::unique_ptr<WakeFd> wake_;
    std::atomic<bool> stopping_{false};
    std::vector<char> buffer_;                       // one read; the reader thread only

    mutable std::mutex mutex_;                       // guards what follows
    mutable std::condition_variable fixReady_;
    std::deque<Fix> queue_;
    std::optional<Fix> latest_;
    LiveStats stats_;
    std::uint64_t sequence_ = 0;
    bool stopped_ = false;

    std::mutex stopMutex_;                           // one stop() joins
    std::thread thread_;
};

}  // namespace orbis::livefeed
