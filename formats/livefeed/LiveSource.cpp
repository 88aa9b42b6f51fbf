#include "formats/livefeed/LiveSource.h"

#include "base/Log.h"
#include "formats/livefeed/Socket.h"

#include <poll.h>
#include <pthread.h>
#include <sys/socket.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <exception>
#include <system_error>

namespace orbis::livefeed {
namespace {

/// The longest a reader sleeps in poll() without looking at the clock (flushes are checked then;
/// stop() does not depend on it: it wakes poll() through the eventfd).
constexpr std::chrono::milliseconds kPollSlice{50};
/// One recv(): the largest UDP datagram fits.
constexpr std::size_t kReadBytes = 65536;
/// Datagrams taken per wake-up before the queue is published (keeps latency low under load).
constexpr int kDatagramsPerWake = 64;

TimeNs systemNow() {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch()).count();
}

}  // namespace

Result<std::unique_ptr<LiveSource>> LiveSource::open(std::string_view url, LiveSourceOptions options) {
    Result<FeedAddress> address = parseFeedAddress(url);
    if (!address) return address.error();
    // Guard the loop against settings that would make it spin or never retry.
    options.reconnectMin = std::max(options.reconnectMin, std::chrono::milliseconds(10));
    options.reconnectMax = std::max(options.reconnectMax, options.reconnectMin);
    options.connectTimeout = std::max(options.connectTimeout, std::chrono::milliseconds(10));
    options.queueCapacity = std::max<std::size_t>(options.queueCapacity, 1);
    if (!options.referenceTime) options.referenceTime = systemNow();

    std::unique_ptr<LiveSource> source(new LiveSource(std::move(*address), options));
    if (!source->wake_->valid())
        return makeError("live feed '" + std::string(url) + "': cannot create an eventfd: " + std::strerror(errno));
    try {
        source->thread_ = std::thread([s = source.get()] { s->run(); });
    } catch (const std::system_error& e) {
        return makeError("live feed '" + std::string(url) + "': cannot start its thread: " + e.what());
    }
    return source;
}

LiveSource::LiveSource(FeedAddress address, LiveSourceOptions options)
    : address_(std::move(address)), options_(options), wake_(std::make_unique<WakeFd>()) {
    stats_.address = address_.text;
}

LiveSource::~LiveSource() { stop(); }

void LiveSource::stop() {
    std::lock_guard<std::mutex> guard(stopMutex_);
    stopping_ = true;
    wake_->signal();
    if (thread_.joinable()) thread_.join();
}

std::vector<Fix> LiveSource::drain() {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<Fix> out(std::make_move_iterator(queue_.begin()), std::make_move_iterator(queue_.end()));
    queue_.clear();
    return out;
}

std::optional<Fix> LiveSource::latest() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return latest_;
}

LiveStats LiveSource::stats() const {
    std::lock_guard<std::mutex> lock(mutex_);
    LiveStats s = stats_;
    s.queued = queue_.size();
    return s;
}

bool LiveSource::waitForFixes(std::chrono::milliseconds timeout) const {
    std::unique_lock<std::mutex> lock(mutex_);
    fixReady_.wait_for(lock, timeout, [&] { return !queue_.empty() || stopped_; });
    return !queue_.empty();
}

void LiveSource::setError(std::string message) {
    std::lock_guard<std::mutex> lock(mutex_);
    stats_.lastError = std::move(message);
}

void LiveSource::run() {
    pthread_setname_np(pthread_self(), "orbis-livefeed");
    try {
        loop();
    } catch (const std::exception& e) {
        setError("live feed '" + address_.text + "': reader stopped by an unexpected error: " + e.what());
        log::error("live feed '", address_.text, "': reader stopped by an unexpected error: ", e.what());
    } catch (...) {
        setError("live feed '" + address_.text + "': reader stopped by an unexpected error");
        log::error("live feed '", address_.text, "': reader stopped by an unexpected error");
    }
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stats_.connected = false;
        stopped_ = true;
    }
    fixReady_.notify_all();
}

void LiveSource::loop() {
    DecoderOptions decoderOptions;
    decoderOptions.requireChecksum = options_.requireChecksum;
    decoderOptions.referenceTime = *options_.referenceTime;
    const std::unique_ptr<FixDecoder> decoder = makeDecoder(options_.protocol, decoderOptions);
    buffer_.resize(kReadBytes);
    const bool udp = address_.transport == Transport::Udp;

    std::chrono::milliseconds backoff = options_.reconnectMin;
    bool failing = false;   // in a streak of failed attempts (logged once)
    while (!stopping_) {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            ++stats_.connectAttempts;
        }
        Result<Fd> fd = makeError("");
        Result<std::vector<ResolvedAddress>> addresses = resolve(address_);
        if (!addresses) {
            fd = addresses.error();
        } else if (udp) {
            fd = bindUdp(address_, addresses->front());
        } else {
            for (const ResolvedAddress& a : *addresses) {
                fd = connectTcp(address_, a, options_.connectTimeout, wake_->fd());
                if (fd || stopping_) break;
            }
        }
        if (stopping_) break;

        if (fd) {
            {
                std::lock_guard<std::mutex> lock(mutex_);
                ++stats_.connections;
                if (stats_.connections > 1) ++stats_.reconnects;
                stats_.connected = true;
                stats_.localPort = localPort(fd->get());
            }
            log::info("live feed '", address_.text, "': ", udp ? "listening" : "connected");
            failing = false;
            decoder->resetInput();
            bool gotData = false;
            const std::string why = readConnection(fd->get(), *decoder, gotData);
            fd->reset();
            std::vector<Fix> rest;
            decoder->flush(Clock::now(), rest);
            decoder->resetInput();
            publish(rest, *decoder);
            {
                std::lock_guard<std::mutex> lock(mutex_);
                stats_.connected = false;
                if (!why.empty()) ++stats_.disconnects;
            }
            if (stopping_ || why.empty()) break;
            setError(why);
            log::warn(why, "; reconnecting");
            if (gotData) backoff = options_.reconnectMin;
        } else {
            setError(fd.message());
            if (!failing) log::warn(fd.message(), "; retrying every ", backoff.count(), " to ", options_.reconnectMax.count(), " ms");
            failing = true;
        }
        if (waitFor(-1, 0, wake_->fd(), backoff) == WaitResult::Woken) break;
        backoff = std::min(backoff * 2, options_.reconnectMax);
    }
}

std::string LiveSource::readConnection(int fd, FixDecoder& decoder, bool& gotData) {
    const bool udp = address_.transport == Transport::Udp;
    const std::string what = "live feed '" + address_.text + "'";
    const auto slice = std::min(kPollSlice, std::max(options_.flushAfterSilence, std::chrono::milliseconds(1)));
    std::vector<Fix> fixes;
    Clock::time_point lastData = Clock::now();
    bool flushed = true;
    for (;;) {
        const WaitResult w = waitFor(fd, POLLIN, wake_->fd(), slice);
        if (w == WaitResult::Woken) return {};
        if (w == WaitResult::Failed) return what + ": poll: " + std::strerror(errno);
        if (w == WaitResult::TimedOut) {
            if (!flushed && Clock::now() - lastData >= options_.flushAfterSilence) {
                decoder.flush(Clock::now(), fixes);
                flushed = true;
                publish(fixes, decoder);
            }
            continue;
        }
        // Readable, closed or failed: recv() says which. Never send(): no SIGPIPE to fear.
        for (int i = 0; i < (udp ? kDatagramsPerWake : 1); ++i) {
            const ssize_t n = ::recv(fd, buffer_.data(), buffer_.size(), MSG_DONTWAIT);
            const Clock::time_point stamp = Clock::now();
            if (n < 0) {
                if (errno == EINTR) continue;
                if (errno == EAGAIN || errno == EWOULDBLOCK) break;
                return what + ": read: " + std::strerror(errno);
            }
            if (n == 0 && !udp) return what + ": the server closed the connection";
            decoder.feed(std::string_view(buffer_.data(), std::size_t(n)), stamp, fixes);
            if (udp) decoder.endOfRecord(stamp, fixes);
            lastData = stamp;
            flushed = false;
            gotData = true;
        }
        publish(fixes, decoder);
    }
}

void LiveSource::publish(std::vector<Fix>& fixes, const FixDecoder& decoder) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        for (Fix& f : fixes) {
            f.sequence = ++sequence_;
            latest_ = f;
            queue_.push_back(std::move(f));
            if (queue_.size() > options_.queueCapacity) {
                queue_.pop_front();
                ++stats_.dropped;
            }
            ++stats_.fixesReceived;
        }
        stats_.decoded = decoder.counters();
        stats_.protocol = decoder.protocol() != FeedProtocol::Auto ? decoder.protocol() : stats_.protocol;
        stats_.maxBufferedBytes = std::max(stats_.maxBufferedBytes, decoder.bufferedBytes());
    }
    if (!fixes.empty()) fixReady_.notify_all();
    fixes.clear();
}

}  // namespace orbis::livefeed
