// orbis info [FILE]: the GPU and what Orbis uses of it, or what a file holds.
#include "tools/orbis/Commands.h"

#include "engine/scene/SceneDesc.h"
#include "layers/BuiltinLayers.h"
#include "tools/orbis/Session.h"

#include "globe/OgcCapabilities.h"
#include "globe/RasterSource.h"
#include "formats/fmv/KlvFile.h"
#include "formats/fmv/PoseCsv.h"
#include "layers/fmv/VideoFile.h"
#include "layers/models/GltfModel.h"
#include "layers/models/MeshModel.h"
#include "layers/points/PointCloud.h"
#include "layers/vector/VectorReader.h"
#include "layers/volume/VolumeReader.h"

#include <nlohmann/json.hpp>

#include <cctype>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <filesystem>

namespace orbis::cli {

namespace {
const char* kHelp =
    "usage: orbis info [FILE] [options]\n"
    "Without FILE: the Vulkan devices, the one Orbis would pick, its driver and the features used.\n"
    "With FILE: what the file holds, as JSON. Readers so far: scene files (.json), point clouds (LAS\n"
    "1.0-1.4 and LAZ: header, compression, VLRs, CRS, bounds on the globe, first points), volumes (netCDF and other\n"
    "multidimensional files: variables, dimensions, ranges), rasters (GDAL), vector data (anything OGR\n"
    "opens that is not a raster: Shapefile, GeoPackage, GeoJSON, ...: layers, geometry types, counts,\n"
    "CRS, fields, extents in WGS84), 3-D models (glTF, OBJ, FBX, COLLADA, KMZ, 3DS, PLY, STL: triangles,\n"
    "materials, textures, size in metres with +Y up as drawn, what was left out, the time to read it),\n"
    "and FMV metadata:\n"
    "raw MISB ST 0601 KLV streams (.bin, .klv, or a file that starts with the ST 0601 key) and pose\n"
    "CSV sidecars (.csv), printed as JSON lines, one per packet or row; videos (.ts, .mpg, .mp4, ...):\n"
    "a line on the video stream, then one per ST 0601 packet of its KLV stream with its time.\n"
    "With an http(s):// URL of a .las/.laz file: the point cloud, read with range requests. With any\n"
    "other http(s):// URL (or WMS:/WMTS:/WFS: before it): what the OGC server's WMS, WMTS and WFS\n"
    "offer, from their GetCapabilities: layers and feature types with titles, styles, CRSs, WGS84\n"
    "extents, time; WMTS layers also their formats and tile matrix sets.\n";

std::string version(uint32_t v) {
    return std::to_string(VK_API_VERSION_MAJOR(v)) + "." + std::to_string(VK_API_VERSION_MINOR(v)) + "." +
           std::to_string(VK_API_VERSION_PATCH(v));
}

int deviceInfo(const Args& args) {
    GpuSession gpu = openGpu(args);
    const gpu::Device& d = *gpu.device;
    nlohmann::json out;
    for (const auto& pd : gpu::Device::enumerate(*gpu.instance))
        out["devices"].push_back({{"name", pd.name}, {"type", pd.type}, {"api", version(pd.apiVersion)}});
    const auto& f = d.features();
    const auto& limits = d.properties().limits;
    VkPhysicalDeviceMemoryProperties mem;
    vkGetPhysicalDeviceMemoryProperties(d.physical(), &mem);
    nlohmann::json heaps = nlohmann::json::array();
    for (uint32_t i = 0; i < mem.memoryHeapCount; ++i)
        heaps.push_back({{"bytes", mem.memoryHeaps[i].size},
                         {"deviceLocal", bool(mem.memoryHeaps[i].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT)}});
    out["selected"] = {
        {"name", d.info().name},
        {"type", d.info().type},
        {"api", version(d.info().apiVersion)},
        {"driver", d.info().driverInfo},
        {"validation", gpu.instance->validationEnabled()},
        {"featuresUsed",
         {{"dynamicRendering", true},
          {"synchronization2", true},
          {"timelineSemaphore", true},
          {"timestamps", f.timestamps},
          {"shaderInt64", f.shaderInt64},
          {"shaderFloat64", f.shaderFloat64},
          {"shaderBufferInt64Atomics", f.bufferInt64Atomics},
          {"samplerAnisotropy", f.samplerAnisotropy},
          {"fillModeNonSolid", f.fillModeNonSolid}}},
        {"limits",
         {{"maxImageDimension2D", limits.maxImageDimension2D},
          {"maxImageDimension3D", limits.maxImageDimension3D},
          {"maxImageArrayLayers", limits.maxImageArrayLayers},
          {"maxStorageBufferRange", limits.maxStorageBufferRange},
          {"maxPushConstantsSize", limits.maxPushConstantsSize},
          {"timestampPeriodNs", limits.timestampPeriod}}},
        {"memoryHeaps", heaps}};
    std::printf("%s\n", out.dump(2).c_str());
    return kOk;
}

/// One JSON line per packet (or undecodable packet, or run of skipped bytes), in stream order;
/// problems summed up on stderr. Exit 1 when nothing in the file decodes.
int klvInfo(const std::string& file, const fmv::KlvStream& stream) {
    std::size_t gap = 0;
    auto flushGapsBefore = [&](uint64_t offset) {
        for (; gap < stream.gaps.size() && stream.gaps[gap].offset < offset; ++gap)
            std::printf("%s\n", nlohmann::json{{"offset", stream.gaps[gap].offset}, {"skipped", stream.gaps[gap].bytes}}.dump().c_str());
    };
    for (const fmv::KlvRecord& r : stream.records) {
        flushGapsBefore(r.offset);
        if (r.packet) std::printf("%s\n", fmv::st0601JsonLine(*r.packet, r.offset).c_str());
        else std::printf("%s\n", nlohmann::json{{"offset", r.offset}, {"error", r.error}}.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace).c_str());
    }
    flushGapsBefore(UINT64_MAX);
    const std::size_t decoded = stream.decodedCount(), broken = stream.records.size() - decoded, sums = stream.checksumErrors();
    uint64_t skipped = 0;
    for (const auto& g : stream.gaps) skipped += g.bytes;
    if (decoded == 0) {
        std::fprintf(stderr, "orbis: %s: none of its %zu ST 0601 packets decodes\n", file.c_str(), broken);
        return kBadInput;
    }
    if (broken || sums || skipped)
        std::fprintf(stderr, "orbis: %s: %zu packets decoded, %zu with a wrong checksum, %zu undecodable, %llu bytes skipped\n",
                     file.c_str(), decoded, sums, broken, static_cast<unsigned long long>(skipped));
    return kOk;
}

bool looksLikeVideo(const std::string& ext) {
    for (const char* e : {".ts", ".m2ts", ".mts", ".mpg", ".mpeg", ".mp4", ".mov", ".mkv", ".avi"})
        if (ext == e) return true;
    return false;
}

/// A video: one JSON line on its video stream, then one per ST 0601 packet of its KLV stream
/// (the packet's time on the video's clock first).
int videoInfo(const std::string& file) {
    auto opened = fmv::VideoFile::open(file);
    if (!opened) return badInput(opened.message());
    const fmv::VideoFile& video = **opened;
    const fmv::VideoInfo& info = video.info();
    std::printf("%s\n", nlohmann::ordered_json{{"video",
                                               {{"codec", info.codec},
                                                {"width", info.width},
                                                {"height", info.height},
                                                {"frames", video.frameCount()},
                                                {"frameRate", info.frameRate},
                                                {"duration", info.duration},
                                                {"klvPackets", video.klv().size()}}}}
                             .dump()
                             .c_str());
    size_t decoded = 0, broken = 0, sums = 0;
    for (size_t k = 0; k < video.klv().size(); ++k) {
        const fmv::TimedKlv& packet = video.klv()[k];
        const fmv::KlvStream stream = fmv::decodeKlvStream(packet.bytes);
        for (const fmv::KlvRecord& r : stream.records) {
            nlohmann::ordered_json line{{"time", packet.time}, {"packet", k}};
            if (r.packet) {
                line.update(nlohmann::ordered_json::parse(fmv::st0601JsonLine(*r.packet, r.offset)));
                ++decoded;
                sums += r.packet->checksum == fmv::ChecksumVerdict::Mismatch;
            } else {
                line["offset"] = r.offset;
                line["error"] = r.error;
                ++broken;
            }
            std::printf("%s\n", line.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace).c_str());
        }
    }
    if (!info.hasKlv) std::fprintf(stderr, "orbis: %s: no KLV metadata stream\n", file.c_str());
    else if (broken || sums)
        std::fprintf(stderr, "orbis: %s: %zu ST 0601 packets decoded, %zu with a wrong checksum, %zu undecodable\n", file.c_str(),
                     decoded, sums, broken);
    return kOk;
}

/// A pose CSV: one JSON line per row, its line number and the fields its columns gave.
int poseCsvInfo(const fmv::PoseCsv& csv) {
    for (const fmv::PoseSample& s : csv.samples) {
        auto j = nlohmann::ordered_json::parse(fmv::st0601JsonLine(s.pose, 0));
        for (const char* k : {"offset", "size", "checksum", "warnings"}) j.erase(k);
        nlohmann::ordered_json row{{"line", s.line}};
        row.update(j);
        std::printf("%s\n", row.dump().c_str());
    }
    return kOk;
}

/// A reader's description (JSON) on stdout, or its problem on stderr.
/// A 3-D model as the model layer reads it.
int modelInfo(const std::string& file) {
    const auto t0 = std::chrono::steady_clock::now();
    auto m = models::isMeshFormat(file) ? models::loadMesh(file) : models::loadGltf(file);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (!m) return badInput(m.message());
    nlohmann::json textures = nlohmann::json::array();
    for (const models::ModelTexture& t : m->textures) textures.push_back({{"name", t.name}, {"width", t.width}, {"height", t.height}});
    nlohmann::json materials = nlohmann::json::array();
    for (const models::ModelMaterial& x : m->materials)
        materials.push_back({{"name", x.name}, {"baseColor", {x.baseColorFactor.r, x.baseColorFactor.g, x.baseColorFactor.b, x.baseColorFactor.a}},
                             {"texture", x.baseColorTexture}});
    const glm::dvec3 size = m->boundsMax - m->boundsMin;
    nlohmann::json out = {{"file", file},
                          {"kind", "3-D model"},
                          {"reader", models::isMeshFormat(file) ? "Assimp" : "glTF"},
                          {"triangles", m->triangles},
                          {"vertices", m->vertices.size()},
                          {"primitives", m->primitives.size()},
                          {"draws", m->draws.size()},
                          {"materials", materials},
                          {"textures", textures},
                          {"animated", m->animated()},
                          {"sizeMetres", {size.x, size.y, size.z}},
                          {"boundsMin", {m->boundsMin.x, m->boundsMin.y, m->boundsMin.z}},
                          {"boundsMax", {m->boundsMax.x, m->boundsMax.y, m->boundsMax.z}},
                          {"warnings", m->warnings},
                          {"readSeconds", seconds}};
    std::printf("%s\n", out.dump(2).c_str());
    return kOk;
}

int printDescription(const Result<std::string>& json) {
    if (!json) return badInput(json.message());
    std::printf("%s\n", json->c_str());
    return kOk;
}

int sceneInfo(const std::string& file) {
    auto desc = scene::parseSceneFile(file);
    if (!desc) return badInput(desc.message());
    scene::LayerRegistry registry;
    layers::registerBuiltinLayers(registry);
    nlohmann::json out;
    out["kind"] = "scene";
    out["file"] = file;
    out["name"] = desc->name;
    out["viewpoint"] = scene::viewpointToJson(desc->viewpoint);
    out["time"] = {{"start", formatIso8601(desc->time.start)},
                   {"end", formatIso8601(desc->time.end)},
                   {"current", formatIso8601(desc->time.current)}};
    for (const auto& l : desc->layers) {
        nlohmann::json layer = {{"type", l.type}, {"name", l.name}, {"visible", l.visible}};
        if (!registry.has(l.type)) layer["problem"] = "unknown layer type";
        out["layers"].push_back(layer);
    }
    std::printf("%s\n", out.dump(2).c_str());
    return kOk;
}
}  // namespace

int infoCommand(const std::vector<std::string>& argv) {
    std::set<std::string> flags = gpuFlagOptions();
    flags.insert("--help");
    Args args(argv, gpuValuedOptions(), flags, {{"-h", "--help"}});
    if (args.flag("--help")) {
        std::printf("%s%s", kHelp, gpuOptionsHelp().c_str());
        return kOk;
    }
    if (args.positional().size() > 1) throw UsageError{"info expects at most one FILE"};
    if (args.positional().empty()) return deviceInfo(args);
    const std::string file = args.positional()[0];
    // A point cloud on a web server (read with range requests).
    if ((file.rfind("http://", 0) == 0 || file.rfind("https://", 0) == 0) && points::looksLikeLas(file.substr(0, file.find('?'))))
        return printDescription(points::describeLasJson(file));
    // An OGC server: what its WMS, WMTS and WFS offer (GetCapabilities).
    for (const char* prefix : {"http://", "https://", "WMS:http", "WMTS:http", "WFS:http"})
        if (file.rfind(prefix, 0) == 0) return printDescription(globe::describeOgcServices(file));
    std::error_code ec;
    if (!std::filesystem::exists(file, ec)) return badInput(file + ": no such file");
    const std::string ext = std::filesystem::path(file).extension().string();
    if (ext == ".json") return sceneInfo(file);
    {
        std::string lowerExt = ext;
        for (char& c : lowerExt) c = char(std::tolower(static_cast<unsigned char>(c)));
        if (lowerExt == ".glb" || lowerExt == ".gltf" || models::isMeshFormat(file)) return modelInfo(file);
    }
    // LAS point clouds (by extension or the "LASF" signature).
    if (points::looksLikeLas(file)) return printDescription(points::describeLasJson(file));
    // MISB ST 0601 KLV streams (.bin/.klv or the key at the start). A .bin without the key
    // anywhere may be something else (an ENVI raster): the other readers get their turn.
    std::string klvProblem;
    if (fmv::looksLikeKlv(file)) {
        auto stream = fmv::readKlvFile(file);
        if (stream) return klvInfo(file, *stream);
        std::string lowerExt = ext;
        for (char& c : lowerExt) c = char(std::tolower(static_cast<unsigned char>(c)));
        if (lowerExt != ".bin") return badInput(stream.message());
        klvProblem = stream.message();
    }
    if (looksLikeVideo(ext)) return videoInfo(file);
    // Pose CSV sidecars of FMV (a header that names time, latitude, longitude and altitude).
    if ((ext == ".csv" || ext == ".CSV") && fmv::looksLikePoseCsv(file)) {
        auto csv = fmv::readPoseCsv(file);
        if (csv) return poseCsvInfo(*csv);
        return badInput(csv.message());
    }
    // Files with variables of three or more dimensions (netCDF, HDF5, Zarr): the volume reader.
    if (layers::looksLikeVolumeFile(file)) {
        // Shown whole, but text that is not UTF-8 is a defect of the file: named, and exit 1.
        std::vector<std::string> problems;
        const int status = printDescription(layers::describeVolumeJson(file, &problems));
        for (const std::string& p : problems) std::fprintf(stderr, "orbis: %s\n", p.c_str());
        return problems.empty() ? status : kBadInput;
    }
    // Everything else is tried as a raster (GeoTIFF, DTED, VRT, JP2, netCDF 2-D, ...).
    auto raster = globe::describeRasterJson(file);
    if (raster) {
        std::printf("%s\n", raster->c_str());
        return kOk;
    }
    // Then as vector data (Shapefile, GeoPackage, GeoJSON, CSV with geometry, ...): only files
    // no reader above took, and only with a layer that has a geometry.
    if (vector::looksLikeVectorFile(file)) return printDescription(vector::describeVectorJson(file));
    if (!klvProblem.empty()) std::fprintf(stderr, "orbis: %s\n", klvProblem.c_str());
    std::fprintf(stderr, "orbis: %s\n", raster.message().c_str());
    std::fprintf(stderr,
                 "orbis: %s: no reader for this file (readers: scene .json, LAS point clouds, netCDF volumes, rasters GDAL opens, "
                 "vector data OGR opens, ST 0601 KLV .bin/.klv, pose .csv)\n",
                 file.c_str());
    return kBadInput;
}

}  // namespace orbis::cli
