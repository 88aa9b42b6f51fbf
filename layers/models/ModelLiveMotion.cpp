// A model on a live position feed (formats/livefeed): the fixes received so far form a growing
// trajectory on their own GPS times, so the model is where the feed said it was at the scene's
// virtual time, and at its latest fix (held) for any later time. A viewer that follows the feed
// keeps its TimeServer at the latest fix's time; seeking back replays the history.
// Each fix is appended to the trajectory in amortised O(1) (Trajectory::append); the history
// is cut back to kMaxHistory fixes once it holds a quarter more (an O(n) rebuild every
// kMaxHistory / 4 fixes).
#include "base/Log.h"
#include "engine/scene/JsonReader.h"
#include "globe/Ellipsoid.h"
#include "formats/livefeed/LiveSource.h"
#include "layers/models/ModelMotion.h"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace orbis::models {
namespace {

/// Fixes kept as the trajectory (about 3 hours at 1 Hz, 17 minutes at 10 Hz).
constexpr std::size_t kMaxHistory = 10'000;
/// Latencies kept for the median (socket -> the frame that takes the fix).
constexpr std::size_t kMaxLatencies = 1'000;

class LiveMotion final : public ModelMotion {
public:
    LiveMotion(std::unique_ptr<livefeed::LiveSource> source, bool onGround)
        : source_(std::move(source)), onGround_(onGround) {}

    void update() override {
        std::vector<livefeed::Fix> fixes = source_->drain();
        if (fixes.empty()) return;
        const auto now = livefeed::LiveSource::Clock::now();
        motion::TrajectoryOptions o;
        o.interpolation = motion::Interpolation::Linear;   // a live feed has no future samples to bend towards
        for (const livefeed::Fix& f : fixes) {
            latencies_.push_back(std::chrono::duration<double, std::milli>(now - f.received).count());
            if (trajectory_ && f.time <= trajectory_->timeRange().end) {   // out of order or repeated epoch
                ++outOfOrder_;
                continue;
            }
            motion::TrajectorySample s;
            s.t = f.time;
            s.lonDeg = f.lonDeg;
            s.latDeg = f.latDeg;
            if (onGround_) {
                s.alt = 0.0;
                s.altRef = motion::AltitudeRef::Ground;
            } else if (f.heightEllipsoid) {
                s.alt = *f.heightEllipsoid;
            } else if (f.altitudeMsl) {
                s.alt = *f.altitudeMsl;
                s.altRef = motion::AltitudeRef::MeanSeaLevel;
            } else {
                s.altRef = motion::AltitudeRef::Ground;   // no height at all: on the ground
            }
            s.headingDeg = f.headingDeg ? f.headingDeg : f.courseDeg;
            s.pitchDeg = f.pitchDeg;
            s.rollDeg = f.rollDeg;
            s.line = std::size_t(f.sequence);
            if (!trajectory_) {
                auto t = motion::Trajectory::create({s}, o, source_->address().host + ":" + std::to_string(source_->address().port));
                if (t) trajectory_ = std::move(*t);
                else log::warn("live feed ", source_->stats().address, ": ", t.message());
            } else if (auto r = trajectory_->append(s); !r) {
                log::warn("live feed ", source_->stats().address, ": ", r.message());
            }
        }
        if (trajectory_ && trajectory_->sampleCount() > kMaxHistory + kMaxHistory / 4) trajectory_->keepLast(kMaxHistory);
        if (latencies_.size() > kMaxLatencies) latencies_.erase(latencies_.begin(), latencies_.begin() + long(latencies_.size() - kMaxLatencies));
    }

    std::optional<scene::TrackedPose> pose(TimeNs t, const GroundFn& ground) const override {
        if (!trajectory_) return std::nullopt;
        auto p = trajectory_->pose(t, ground ? &ground : nullptr);
        if (!p) return std::nullopt;
        motion::followGround(*p, footprint_, ground);
        return toTrackedPose(*p);
    }
    void setFootprint(const motion::Footprint& footprint) override { footprint_ = footprint; }
    std::optional<scene::TimeRange> range() const override {
        if (!trajectory_) return std::nullopt;
        return scene::TimeRange{trajectory_->timeRange().begin, trajectory_->timeRange().end};
    }
    std::vector<glm::dvec3> path(TimeNs from, TimeNs to, std::size_t maxPoints, const GroundFn& ground) const override {
        if (!trajectory_) return {};
        return trajectory_->pathEcef(from, to, maxPoints, ground ? &ground : nullptr);
    }
    scene::ContentBounds bounds() const override {
        if (!trajectory_) return {};
        return {trajectory_->bounds().centerEcef, trajectory_->bounds().radius};
    }
    bool usesGround() const override { return true; }
    std::string status() const override {
        const livefeed::LiveStats s = source_->stats();
        std::string out = "live " + s.address + ": " + (s.connected ? "connected" : "not connected") + ", " +
                          std::to_string(s.fixesReceived) + " fixes, " + std::to_string(s.reconnects) + " reconnects, " +
                          std::to_string(s.decoded.badChecksum) + " bad checksums, " +
                          std::to_string(outOfOrder_) + " out of order";
        if (const auto m = medianLatencyMs()) out += ", latency " + std::to_string(*m) + " ms (median)";
        if (!s.lastError.empty()) out += "; " + s.lastError;
        return out;
    }
    std::optional<double> medianLatencyMs() const {
        if (latencies_.empty()) return std::nullopt;
        std::vector<double> v = latencies_;
        std::nth_element(v.begin(), v.begin() + long(v.size() / 2), v.end());
        return v[v.size() / 2];
    }

private:
    std::unique_ptr<livefeed::LiveSource> source_;
    bool onGround_;
    std::optional<motion::Trajectory> trajectory_;
    std::vector<double> latencies_;
    std::uint64_t outOfOrder_ = 0;
    motion::Footprint footprint_;
};

}  // namespace

Result<std::unique_ptr<ModelMotion>> makeLiveMotion(const nlohmann::json& json, const std::string& file, const std::string& path) {
    scene::JsonReader r(json, file, path);
    const auto url = r.string("url");
    if (r.ok() && (!url || url->empty())) r.fail("url", "name the feed: tcp://host:port or udp://host:port");
    livefeed::LiveSourceOptions o;
    if (auto p = r.string("protocol", std::string("auto"))) {
        if (*p == "auto") o.protocol = livefeed::FeedProtocol::Auto;
        else if (*p == "nmea") o.protocol = livefeed::FeedProtocol::Nmea;
        else if (*p == "xml") o.protocol = livefeed::FeedProtocol::Xml;
        else r.fail("protocol", "expected \"nmea\", \"xml\" or \"auto\", got \"" + *p + "\"");
    }
    bool onGround = false;
    if (auto a = r.string("altitude", std::string("ellipsoid"))) {
        if (*a == "ground") onGround = true;
        else if (*a != "ellipsoid") r.fail("altitude", "expected \"ellipsoid\" (the feed's heights) or \"ground\", got \"" + *a + "\"");
    }
    if (auto done = r.finish(); !done) return done.error();
    auto source = livefeed::LiveSource::open(*url, o);
    if (!source) return makeError(file + ": " + path + "/url: " + source.message());
    return std::unique_ptr<ModelMotion>(std::make_unique<LiveMotion>(std::move(*source), onGround));
}

}  // namespace orbis::models
