#pragma once
// The modes of `orbis bench` besides the plain frame timing (BenchCommand.cpp), each in its
// own file. They return the command's exit code and throw UsageError on bad options.

#include "engine/render/Renderer.h"
#include "engine/scene/CameraPath.h"
#include "engine/scene/Scene.h"
#include "tools/orbis/Args.h"
#include "tools/orbis/Session.h"

#include <cstdint>
#include <optional>
#include <string>

namespace orbis::cli {

/// Sets a live setting (LiveSettings::setParameter) on every visible layer that has it; false
/// when none has it or every one refused the value (BenchSweep.cpp).
bool setOnVisibleLayers(scene::Scene& scene, const std::string& name, double value);
/// `--set K=V` (any number of them): each on the scene's visible layers before anything is
/// measured; kOk, or kBadInput naming the setting no layer took (BenchSweep.cpp).
int applySetOptions(const Args& args, scene::Scene& scene);
/// `orbis bench SCENE --sweep K=v1,v2,...`: one row per value (BenchSweep.cpp).
int sweepBench(const Args& args, GpuSession& gpu, scene::Scene& scene, render::Renderer& renderer, long frames,
               long warmup);
/// `orbis bench SCENE --iso-error N1,N2,...`: isosurface position error against the step
/// count (BenchIsoError.cpp).
int isoErrorBench(const Args& args, GpuSession& gpu, uint32_t width, uint32_t height, long frames, long warmup);
/// `orbis bench SCENE --soak SECONDS [--camera-path FILE]`: a long run with the process and
/// the layers sampled, and bounds on their growth (SoakBench.cpp).
int soakBench(const Args& args, GpuSession& gpu, scene::Scene& scene, render::Renderer& renderer,
              const std::optional<scene::CameraPath>& path, double seconds);
/// `orbis bench SCENE --live N --update SQL`: commit to changed frame, for a live vector
/// layer (LiveBench.cpp).
int liveBench(const Args& args, GpuSession& gpu, scene::Scene& scene, render::Renderer& renderer, long runs);
/// `orbis bench SCENE --feeds SECONDS`: glass-to-drape latency and rates of live FMV feeds
/// (FeedBench.cpp).
int feedBench(GpuSession& gpu, scene::Scene& scene, render::Renderer& renderer, double seconds);
/// `orbis bench SCENE --tiles LEVEL` (TileBench.cpp).
int tileBench(const Args& args, scene::Scene& scene, long level, unsigned threads);
/// `orbis bench --video FILE` (VideoBench.cpp).
int videoBench(const std::string& file, long seeks);
/// `orbis bench --poses FILE` (PoseBench.cpp).
int poseBench(const std::string& file);
/// `orbis bench --labels N [--frames F] [--margin PX]` (LabelBench.cpp).
int labelBench(long count, long frames, double marginPx);
/// `orbis bench --labels N --layer`: the vector layer's label step, VectorLabels (LabelBench.cpp).
int labelLayerBench(long count, long frames, double marginPx);
/// `orbis bench --vector FILE [--level L] [--runs N]` (VectorBench.cpp).
int vectorBench(const std::string& file, long level, long runs);

}  // namespace orbis::cli
