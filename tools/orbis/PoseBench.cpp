// orbis bench --poses FILE: the cost of one glTF pose (layers/models/GltfAnimation.h) on the CPU,
// no GPU: for each animation of the model, poses evaluated at evenly spread times, repeated
// for at least 0.3 s, in batches of 1000 timed one by one: the median and 95th percentile
// microseconds per pose, and the bytes a pose block uploads. An animated model layer pays this
// once per distinct animation time of a frame.
#include "tools/orbis/Commands.h"

#include "layers/models/GltfAnimation.h"
#include "tools/orbis/Session.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <vector>

namespace orbis::cli {
namespace {

using Clock = std::chrono::steady_clock;

double percentile(std::vector<double> v, double p) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, size_t(p * double(v.size() - 1) + 0.5))];
}

}  // namespace

int poseBench(const std::string& file) {
    auto model = models::loadGltf(file);
    if (!model) return badInput(model.message());
    size_t joints = 0;
    for (const auto& s : model->rig.skins) joints += s.joints.size();
    std::printf("orbis bench --poses %s  (CPU only, one thread)\n", file.c_str());
    std::printf("%zu nodes, %zu draws, %zu skins (%zu joints), %zu animations%s\n", model->rig.nodes.size(), model->draws.size(),
                model->rig.skins.size(), joints, model->rig.animations.size(),
                model->animated() ? "" : ": a static model (no pose: the fast path)");
    if (!model->animated()) return kOk;
    std::printf("%-24s %9s %8s %12s %12s\n", "animation", "channels", "bytes", "us/pose p50", "us/pose p95");
    for (int a = -1; a < int(model->rig.animations.size()); ++a) {
        models::PoseEvaluator e(*model, a);
        std::vector<glm::vec4> pose(e.layout().vec4s);
        std::vector<double> batches;
        constexpr int kBatch = 1000;
        double sink = 0.0;
        const auto start = Clock::now();
        for (int i = 0; batches.size() < 20 || std::chrono::duration<double>(Clock::now() - start).count() < 0.3; ++i) {
            const auto t0 = Clock::now();
            for (int k = 0; k < kBatch; ++k) {
                e.evaluate(e.duration() * double((i * kBatch + k) % 997) / 996.0, pose.data());
                sink += pose[0].x;
            }
            batches.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count() / kBatch);
        }
        const std::string name = a < 0 ? "(rest pose)" : model->rig.animations[size_t(a)].name.empty()
                                                             ? std::string("#").append(std::to_string(a))
                                                             : model->rig.animations[size_t(a)].name;
        const size_t channels = a < 0 ? 0 : model->rig.animations[size_t(a)].channels.size();
        std::printf("%-24s %9zu %8zu %12.3f %12.3f%s\n", name.c_str(), channels, pose.size() * sizeof(glm::vec4),
                    percentile(batches, 0.5), percentile(batches, 0.95), sink == 1e300 ? " " : "");
    }
    return kOk;
}

}  // namespace orbis::cli
