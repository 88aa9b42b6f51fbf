// orbis bench --labels N: label placement (layers/vector/LabelPlacement.h) on the CPU, no GPU:
// N candidate labels (text-sized boxes, priorities spread like city populations) over a
// 1920x1080 screen and a tenth beyond each edge, panned 0.5 px a frame for --frames frames
// (default 300): milliseconds per frame (min, median, p95), labels placed, and how many labels
// appeared or went per frame while the view moved (the flicker the hysteresis holds down).
//
// orbis bench --labels N --layer: the vector layer's whole label step on the CPU
// (layers/vector/VectorLabels.h), no GPU: N labelled points (Latin, Greek and Cyrillic names)
// over the part of the globe a 1920x1080 view sees from 4 000 km, the view turning 0.5 px a
// frame: ms per frame to gather the candidates (projection, horizon, layout, boxes), to place
// them (without a ground, then with the terrain test over flat ground) and in all, with the
// candidates and labels.
#include "tools/orbis/BenchModes.h"
#include "tools/orbis/BenchStats.h"

#include "globe/Ellipsoid.h"
#include "layers/vector/LabelPlacement.h"
#include "layers/vector/VectorLabels.h"

#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <cmath>
#include <cstdio>
#include <random>
#include <unordered_set>
#include <vector>

namespace orbis::cli {
namespace {

std::vector<vector::LabelCandidate> syntheticLabels(long count) {
    std::mt19937_64 rng(20261202);
    std::uniform_real_distribution<double> x(-192.0, 2112.0), y(-108.0, 1188.0), chars(3.0, 18.0), unit(0.0, 1.0);
    std::vector<vector::LabelCandidate> out(static_cast<size_t>(count));
    for (size_t i = 0; i < out.size(); ++i) {
        const double w = 7.0 * chars(rng) + 16.0, h = 18.0;   // glyphs, icon and halo
        const glm::dvec2 at{x(rng), y(rng)};
        out[i] = {.id = i, .priority = std::pow(unit(rng), 4.0) * 1e7, .min = at, .max = at + glm::dvec2(w, h)};
    }
    return out;
}

/// N labelled points around (10 E, 45 N), within what the view sees.
std::shared_ptr<vector::VectorContent> syntheticPoints(long count, vector::ContentStyles& styles) {
    std::mt19937_64 rng(20261203);
    std::uniform_real_distribution<double> lon(-18.0, 38.0), lat(31.0, 59.0);
    std::uniform_int_distribution<int> letters(3, 16), script(0, 2);
    const char* alphabets[] = {"abcdefghijklmnopqrstuvwxyzéèàç", "αβγδεζηθικλμνξοπρστυφχψω", "абвгдежзийклмнопрстуфхцчшщыэюя"};
    auto content = std::make_shared<vector::VectorContent>();
    vector::ContentLayer& layer = content->layers.emplace_back();
    styles.assign(1, {});
    for (long i = 0; i < count; ++i) {
        vector::Feature f;
        f.kind = vector::GeometryKind::Points;
        f.coords = {{lon(rng), lat(rng), 0.0}};
        f.parts = {0};
        layer.data.features.push_back(std::move(f));
        // A name of whole UTF-8 characters from one alphabet (2 bytes each beyond ASCII).
        const std::string alphabet = alphabets[script(rng)];
        std::vector<std::string> chars;
        for (size_t b = 0; b < alphabet.size();) {
            const size_t n = (uint8_t(alphabet[b]) & 0x80) ? 2 : 1;
            chars.push_back(alphabet.substr(b, n));
            b += n;
        }
        std::uniform_int_distribution<size_t> pick(0, chars.size() - 1);
        vector::FeatureStyle style;
        for (int c = letters(rng); c > 0; --c) style.label += chars[pick(rng)];
        styles[0].push_back(std::move(style));
    }
    return content;
}

}  // namespace

int labelLayerBench(long count, long frames, double marginPx) {
    auto styles = std::make_shared<vector::ContentStyles>();
    auto content = syntheticPoints(count, *styles);
    auto anchors = std::make_shared<const vector::ContentAnchors>(vector::labelAnchors(*content));
    vector::VectorLabelOptions options;
    options.marginPx = marginPx;
    auto labels = vector::VectorLabels::create(options);
    if (!labels) {
        std::fprintf(stderr, "orbis bench: %s\n", labels.message().c_str());
        return kBadInput;
    }
    labels->setContent(content, styles, anchors);

    // Twice: over flat ground (every label with room pays for its terrain test), then with no
    // ground known (the placement alone). The view turns about the Earth's axis by the angle
    // that moves its centre 0.5 px a frame.
    const auto& wgs84 = globe::Ellipsoid::wgs84();
    struct Series {
        std::vector<double> gather, place, total, candidates, placed;
    };
    const auto run = [&](bool ground) {
        scene::Camera camera;
        camera.lookAt(wgs84.toEcef(10.0, 45.0, 4.0e6), wgs84.toEcef(10.0, 45.0, 0.0), glm::dvec3(0, 0, 1));
        scene::FrameContext frame;
        frame.camera = &camera;
        frame.width = 1920;
        frame.height = 1080;
        if (ground) frame.groundHeight = [](double, double) { return std::optional<double>(0.0); };
        const double metresPerPixel = 2.0 * 4.0e6 * std::tan(0.5 * camera.verticalFovRad()) / frame.height;
        const double stepRad = 0.5 * metresPerPixel / (wgs84.equatorialRadius() * std::cos(45.0 * 3.14159265358979 / 180.0));
        const glm::dmat3 turn(glm::dvec3(std::cos(stepRad), std::sin(stepRad), 0),
                              glm::dvec3(-std::sin(stepRad), std::cos(stepRad), 0), glm::dvec3(0, 0, 1));
        Series out;
        labels->clear();
        for (long f = 0; f < frames; ++f) {
            camera.setPosition(turn * camera.position());
            camera.setOrientation(glm::quat_cast(turn) * camera.orientation());
            labels->update(frame);
            const vector::VectorLabelStats& s = labels->stats();
            if (f == 0) continue;   // the first frame lays every label out and fills the atlas
            out.gather.push_back(s.gatherMs);
            out.place.push_back(s.placementMs);
            out.total.push_back(s.frameMs);
            out.candidates.push_back(double(s.candidates));
            out.placed.push_back(double(s.placed));
        }
        return out;
    };
    const Series flat = run(true), bare = run(false);

    std::printf("orbis bench --labels %ld --layer  (CPU only, one thread; 1920x1080 from 4000 km, turned 0.5 px a frame, margin %.1f px)\n",
                count, marginPx);
    std::printf("%-36s %10s %10s %10s\n", "", "min", "median", "p95");
    const auto row = [](const char* name, const char* format, const std::vector<double>& values) {
        const Stats s = summarize(values);
        std::printf(format, name, s.min, s.median, s.p95);
    };
    row("gather ms/frame", "%-36s %10.3f %10.3f %10.3f\n", flat.gather);
    row("placement ms/frame", "%-36s %10.3f %10.3f %10.3f\n", bare.place);
    row("placement + terrain tests ms/frame", "%-36s %10.3f %10.3f %10.3f\n", flat.place);
    row("labels ms/frame (all, terrain tests)", "%-36s %10.3f %10.3f %10.3f\n", flat.total);
    row("candidates", "%-36s %10.0f %10.0f %10.0f\n", flat.candidates);
    row("labels placed", "%-36s %10.0f %10.0f %10.0f\n", flat.placed);
    return kOk;
}

int labelBench(long count, long frames, double marginPx) {
    auto labels = syntheticLabels(count);
    const vector::LabelPlacementOptions options{.screen = {1920.0, 1080.0}, .marginPx = marginPx};
    vector::LabelPlacer placer;
    std::vector<double> ms, placed, changes;
    std::unordered_set<uint64_t> before;
    for (long f = 0; f < frames; ++f) {
        for (auto& l : labels) {
            l.min += glm::dvec2(0.5, 0.25);
            l.max += glm::dvec2(0.5, 0.25);
        }
        const auto t0 = std::chrono::steady_clock::now();
        const auto chosen = placer.place(labels, options);
        ms.push_back(millisecondsSince(t0));
        std::unordered_set<uint64_t> now;
        for (uint32_t i : chosen) now.insert(labels[i].id);
        if (f > 0) {
            size_t changed = 0;
            for (uint64_t id : now) changed += before.count(id) ? 0 : 1;
            for (uint64_t id : before) changed += now.count(id) ? 0 : 1;
            changes.push_back(double(changed));
        }
        placed.push_back(double(chosen.size()));
        before = std::move(now);
    }
    std::printf("orbis bench --labels %ld  (CPU only, one thread; 1920x1080, panned 0.5 px a frame, margin %.1f px)\n", count,
                marginPx);
    std::printf("%-28s %10s %10s %10s\n", "", "min", "median", "p95");
    const auto row = [](const char* name, const char* format, const std::vector<double>& values) {
        const Stats s = summarize(values);
        std::printf(format, name, s.min, s.median, s.p95);
    };
    row("placement ms/frame", "%-28s %10.3f %10.3f %10.3f\n", ms);
    row("labels placed", "%-28s %10.0f %10.0f %10.0f\n", placed);
    row("labels in or out per frame", "%-28s %10.0f %10.0f %10.0f\n", changes);
    return kOk;
}

}  // namespace orbis::cli
