// "Leave out what a scene does not need": a layer type absent from the scene is never
// constructed, and a scene with only the globe builds the globe's pipelines and nothing else:
// no worker thread, no other pipeline.
#include "engine/gpu/Device.h"
#include "engine/render/RenderContext.h"
#include "base/ThreadPool.h"
#include "tests/render/RenderHelpers.h"
#include "tests/support/GpuTest.h"

namespace orbis::test {
namespace {

class LeaveOut : public GpuTest {};

// A stand-in for the heavy layer types (terrain, volume, points, fmv): it counts constructions
// and, if ever prepared, builds a thread pool like a real reader would.
class ProbeLayer : public scene::Layer {
public:
    explicit ProbeLayer(int& prepared) : prepared_(prepared) {}
    std::string_view type() const override { return "probe"; }
    bool drawsIn(scene::Pass) const override { return false; }
    void record(scene::Pass, const render::RecordContext&) override {}

private:
    void onPrepare(const render::RenderServices& s) override {
        ++prepared_;
        s.jobs();
    }

    int& prepared_;
};

void registerProbes(scene::LayerRegistry& registry, int& prepared) {
    for (const char* type : {"terrain", "volume", "points", "fmv", "model"})
        registry.add(type, "probe", [&prepared](const scene::LayerDesc&, const scene::SceneDesc&)
                                        -> Result<std::unique_ptr<scene::Layer>> {
            return std::unique_ptr<scene::Layer>(new ProbeLayer(prepared));
        });
}

TEST_F(LeaveOut, GlobeOnlySceneBuildsNothingElse) {
    scene::LayerRegistry registry;
    layers::registerBuiltinLayers(registry);
    int probesPrepared = 0;
    registerProbes(registry, probesPrepared);

    // llvmpipe starts its rasteriser threads on the first draw: warm the driver up with an
    // empty scene so the baseline counts the driver's threads, and only ours can differ.
    {
        auto empty = buildScene(R"({"layers": []})", registry);
        render::Renderer warm(device(), 64, 64);
        renderOnce(warm, *empty);
    }
    device().waitIdle();
    const int pipelinesBefore = device().counters().pipelines;
    const int threadsBefore = processThreadCount();

    auto scene = buildScene(globeScene(R"({"lon": 0, "lat": 0, "range": 20000000})"), registry);
    ASSERT_TRUE(scene);
    render::Renderer renderer(device(), 64, 64);
    renderOnce(renderer, *scene);

    for (const char* type : {"terrain", "volume", "points", "fmv", "model"})
        EXPECT_EQ(registry.constructed(type), 0) << type << " was constructed";
    EXPECT_EQ(registry.constructed("globe"), 1);
    EXPECT_EQ(probesPrepared, 0);
    // The globe builds exactly two pipelines: surface and sky.
    EXPECT_EQ(device().counters().pipelines - pipelinesBefore, 2);
    EXPECT_FALSE(renderer.jobsStarted());
    EXPECT_EQ(jobs::ThreadPool::liveWorkerThreads(), 0);
    EXPECT_EQ(processThreadCount(), threadsBefore) << "a thread was started for a globe-only scene";
}

TEST_F(LeaveOut, SkyOffBuildsOnePipeline) {
    scene::LayerRegistry registry;
    layers::registerBuiltinLayers(registry);
    device().waitIdle();
    const int before = device().counters().pipelines;
    auto scene = buildScene(globeScene(R"({"lon": 0, "lat": 0, "range": 20000000})", R"(, "sky": false)"), registry);
    ASSERT_TRUE(scene);
    render::Renderer renderer(device(), 64, 64);
    renderOnce(renderer, *scene);
    EXPECT_EQ(device().counters().pipelines - before, 1);
}

TEST_F(LeaveOut, InvisibleLayerIsNeverPrepared) {
    scene::LayerRegistry registry;
    layers::registerBuiltinLayers(registry);
    int probesPrepared = 0;
    registerProbes(registry, probesPrepared);
    device().waitIdle();
    const int pipelinesBefore = device().counters().pipelines;
    auto scene = buildScene(R"({"layers": [{"type": "globe", "visible": false},
                                           {"type": "volume", "visible": false}]})",
                            registry);
    ASSERT_TRUE(scene);
    render::Renderer renderer(device(), 64, 64);
    renderOnce(renderer, *scene);
    EXPECT_EQ(registry.constructed("volume"), 1);   // named by the scene: constructed (cheap) ...
    EXPECT_EQ(probesPrepared, 0);                   // ... but hidden: nothing built for it
    EXPECT_EQ(device().counters().pipelines - pipelinesBefore, 0);
    EXPECT_FALSE(renderer.jobsStarted());

    // Shown later: built then, once.
    scene->resources()[1].visible = true;
    renderOnce(renderer, *scene);
    renderOnce(renderer, *scene);
    EXPECT_EQ(probesPrepared, 1);
    EXPECT_TRUE(renderer.jobsStarted());
}

}  // namespace
}  // namespace orbis::test
