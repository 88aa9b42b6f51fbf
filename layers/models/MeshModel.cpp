// Mesh formats through Assimp into ModelData (MeshModel.h). Every file Assimp opens, the model's
// and its textures, KMZ members included, goes through GDAL's virtual file system (a KMZ is read
// in place through /vsizip/), each checked against the size limit before it is read.
#include "layers/models/MeshModel.h"

#include "layers/models/GltfAnimation.h"
#include "layers/models/GltfImage.h"
#include "layers/models/MeshChecks.h"

#include <assimp/IOStream.hpp>
#include <assimp/IOSystem.hpp>
#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <cpl_error.h>
#include <cpl_string.h>
#include <cpl_vsi.h>
#include <stb_image.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <map>
#include <set>
#include <vector>

namespace orbis::models {
namespace {

namespace fs = std::filesystem;

constexpr int kMaxDepth = 256;
constexpr size_t kMaxAnimatedNodes = 65536;   // a model that animates: each node is evaluated every frame
constexpr uint64_t kMaxTextureFileBytes = uint64_t(64) << 20;

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return s;
}

/// The size of a file through GDAL's virtual file system, or -1.
int64_t vsiSize(const std::string& path) {
    VSIStatBufL st{};
    CPLPushErrorHandler(CPLQuietErrorHandler);
    const int r = VSIStatExL(path.c_str(), &st, VSI_STAT_EXISTS_FLAG | VSI_STAT_NATURE_FLAG | VSI_STAT_SIZE_FLAG);
    CPLPopErrorHandler();
    if (r != 0 || VSI_ISDIR(st.st_mode)) return -1;
    return int64_t(st.st_size);
}

/// A whole file through GDAL's virtual file system, when it exists and is at most `limit` bytes.
bool readVsi(const std::string& path, uint64_t limit, std::vector<uint8_t>& out, std::string& why) {
    const int64_t size = vsiSize(path);
    if (size < 0) {
        why = "not found";
        return false;
    }
    if (uint64_t(size) > limit) {
        why = std::to_string(uint64_t(size) >> 20) + " MiB, more than the " + std::to_string(limit >> 20) + " MiB allowed";
        return false;
    }
    VSILFILE* f = VSIFOpenL(path.c_str(), "rb");
    if (!f) {
        why = "cannot open";
        return false;
    }
    out.resize(size_t(size));
    const bool ok = VSIFReadL(out.data(), 1, out.size(), f) == out.size();
    VSIFCloseL(f);
    if (!ok) why = "cannot read";
    return ok;
}

/// A file Assimp reads, held in memory (read whole, within the size limit).
class MemoryStream : public Assimp::IOStream {
public:
    explicit MemoryStream(std::vector<uint8_t> bytes) : bytes_(std::move(bytes)) {}
    size_t Read(void* buffer, size_t size, size_t count) override {
        if (size == 0) return 0;
        const size_t n = std::min(count, (bytes_.size() - at_) / size);
        std::memcpy(buffer, bytes_.data() + at_, n * size);
        at_ += n * size;
        return n;
    }
    size_t Write(const void*, size_t, size_t) override { return 0; }
    aiReturn Seek(size_t offset, aiOrigin origin) override {
        const size_t base = origin == aiOrigin_SET ? 0 : origin == aiOrigin_CUR ? at_ : bytes_.size();
        if (offset > bytes_.size() - std::min(base, bytes_.size()) && !(origin == aiOrigin_END && offset == 0)) return aiReturn_FAILURE;
        at_ = std::min(bytes_.size(), base + offset);
        return aiReturn_SUCCESS;
    }
    size_t Tell() const override { return at_; }
    size_t FileSize() const override { return bytes_.size(); }
    void Flush() override {}

private:
    std::vector<uint8_t> bytes_;
    size_t at_ = 0;
};

/// Assimp's file access through GDAL's virtual file system, every file within the size limit.
class VsiIoSystem : public Assimp::IOSystem {
public:
    bool Exists(const char* path) const override { return vsiSize(path) >= 0; }
    char getOsSeparator() const override { return '/'; }
    Assimp::IOStream* Open(const char* path, const char* mode) override {
        if (!mode || std::strchr(mode, 'w') || std::strchr(mode, 'a')) return nullptr;
        std::vector<uint8_t> bytes;
        std::string why;
        if (!readVsi(path, kMaxGltfFileBytes, bytes, why)) {
            if (why != "not found" && refused.empty()) refused = std::string(path) + ": " + why;
            return nullptr;
        }
        return new MemoryStream(std::move(bytes));
    }
    void Close(Assimp::IOStream* stream) override { delete stream; }
    std::string refused;   ///< the first file refused for its size
};

uint32_t packColor(const aiColor4D& c) {
    const auto q = [](float v) { return uint32_t(std::lround(std::clamp(std::isfinite(v) ? v : 0.0f, 0.0f, 1.0f) * 255.0f)); };
    return q(c.r) | q(c.g) << 8 | q(c.b) << 16 | q(c.a) << 24;
}

glm::dmat4 toGlm(const aiMatrix4x4& m) {
    glm::dmat4 g;
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) g[c][r] = double(m[r][c]);
    return g;
}

std::optional<double> metaNumber(const aiMetadata* meta, const char* key) {
    if (!meta) return std::nullopt;
    for (unsigned i = 0; i < meta->mNumProperties; ++i) {
        if (std::strcmp(meta->mKeys[i].C_Str(), key) != 0) continue;
        const aiMetadataEntry& e = meta->mValues[i];
        if (!e.mData) return std::nullopt;
        switch (e.mType) {
            case AI_INT32: return double(*static_cast<const int32_t*>(e.mData));
            case AI_UINT64: return double(*static_cast<const uint64_t*>(e.mData));
            case AI_FLOAT: return double(*static_cast<const float*>(e.mData));
            case AI_DOUBLE: return *static_cast<const double*>(e.mData);
            default: return std::nullopt;
        }
    }
    return std::nullopt;
}

/// The unit axis `axis` (0 x, 1 y, 2 z) with `sign`.
glm::dvec3 axisVector(double axis, double sign) {
    glm::dvec3 v(0.0);
    v[std::clamp(int(axis), 0, 2)] = sign < 0 ? -1.0 : 1.0;
    return v;
}

class Reader {
public:
    Reader(const std::string& file, std::string modelPath, const MeshImportOptions& options)
        : file_(file), modelPath_(std::move(modelPath)), options_(options) {}

    /// What Assimp does not bound, checked first (MeshChecks.h).
    Result<void> precheck() const {
        const std::string ext = lower(fs::path(modelPath_).extension().string());
        if (ext != ".ply" && ext != ".dae") return {};
        std::vector<uint8_t> bytes;
        std::string why;
        if (!readVsi(modelPath_, kMaxGltfFileBytes, bytes, why)) return makeError(file_ + ": " + why);
        const std::string_view text(reinterpret_cast<const char*>(bytes.data()), bytes.size());
        const std::string bad = ext == ".ply" ? checkPlyHeader(text.substr(0, 65536), bytes.size()) : checkColladaNodes(text);
        if (!bad.empty()) return makeError(file_ + ": " + bad);
        return {};
    }

    Result<ModelData> read() {
        if (auto r = precheck(); !r) return r.error();
        auto* io = new VsiIoSystem();   // the importer owns it
        Assimp::Importer importer;
        importer.SetIOHandler(io);
        importer.SetPropertyBool(AI_CONFIG_IMPORT_NO_SKELETON_MESHES, true);
        const unsigned flags = aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_GenSmoothNormals | aiProcess_SortByPType |
                               aiProcess_ValidateDataStructure | aiProcess_FlipUVs;
        const aiScene* scene = importer.ReadFile(modelPath_, flags);
        if (!io->refused.empty()) return makeError(file_ + ": " + io->refused);
        if (!scene || !scene->mRootNode) {
            std::string why = importer.GetErrorString();
            while (!why.empty() && (why.back() == '\n' || why.back() == '\r')) why.pop_back();
            return makeError(file_ + ": not a model Orbis can read: " + (why.empty() ? std::string("unknown error") : why));
        }
        if (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) return makeError(file_ + ": the file holds no complete scene (no meshes?)");
        scene_ = scene;
        ModelData out;
        out.file = file_;
        readMaterials(out);
        if (auto r = readMeshes(out); !r) return r.error();
        for (unsigned m = 0; m < scene->mNumMeshes; ++m)
            if (scene->mMeshes[m]->mNumBones > 0) warnOnce(out, "its skins are not read (only glTF skins): their meshes keep the rest pose");
        out.boundsMin = glm::dvec3(std::numeric_limits<double>::max());
        out.boundsMax = glm::dvec3(-std::numeric_limits<double>::max());
        if (auto r = walk(scene->mRootNode, rootTransform(), 0, out); !r) return r.error();
        if (out.draws.empty()) return makeError(file_ + ": the scene has no triangles to draw");
        if (scene->mNumAnimations > 0)
            if (auto r = readAnimations(out); !r) return r.error();
        return out;
    }

private:
    void warnOnce(ModelData& out, const std::string& text) {
        if (warned_.insert(text).second) out.warnings.push_back(text);
    }

    /// File axes and units to glTF's: what the file says (FBX's settings; COLLADA's Assimp
    /// applied), its format's custom, or the options.
    glm::dmat4 rootTransform() const {
        const aiMetadata* meta = scene_->mMetaData;
        const std::string ext = lower(fs::path(modelPath_).extension().string());
        glm::dmat3 axes(1.0);   // columns: where file x, y, z go
        const auto up = metaNumber(meta, "UpAxis"), front = metaNumber(meta, "FrontAxis"), coord = metaNumber(meta, "CoordAxis");
        if (options_.up) {
            if (*options_.up == 'z') axes = glm::dmat3(1, 0, 0, 0, 0, -1, 0, 1, 0);   // x' = x, y' = z, z' = -y
        } else if (up && front && coord) {
            // Rows: the file's right, up and front vectors become glTF's x, y, z.
            const glm::dvec3 r = axisVector(*coord, metaNumber(meta, "CoordAxisSign").value_or(1.0));
            const glm::dvec3 u = axisVector(*up, metaNumber(meta, "UpAxisSign").value_or(1.0));
            const glm::dvec3 f = axisVector(*front, metaNumber(meta, "FrontAxisSign").value_or(1.0));
            axes = glm::transpose(glm::dmat3(r, u, f));
        } else if (ext == ".3ds") {
            axes = glm::dmat3(1, 0, 0, 0, 0, -1, 0, 1, 0);
        }
        double unit = 1.0;
        if (options_.unitMetres) unit = *options_.unitMetres;
        else if (auto cm = metaNumber(meta, "UnitScaleFactor"); cm && std::isfinite(*cm) && *cm > 0.0) unit = *cm / 100.0;
        return glm::dmat4(axes * unit);
    }

    void readMaterials(ModelData& out) {
        std::map<std::string, int> textureOf;   // resolved path -> texture index
        for (unsigned i = 0; i < scene_->mNumMaterials; ++i) {
            const aiMaterial* mat = scene_->mMaterials[i];
            ModelMaterial m;
            aiString name;
            if (mat->Get(AI_MATKEY_NAME, name) == AI_SUCCESS) m.name = name.C_Str();
            aiColor4D colour(1.0f, 1.0f, 1.0f, 1.0f);
            if (mat->Get(AI_MATKEY_BASE_COLOR, colour) != AI_SUCCESS) mat->Get(AI_MATKEY_COLOR_DIFFUSE, colour);
            float opacity = 1.0f;
            if (mat->Get(AI_MATKEY_OPACITY, opacity) == AI_SUCCESS && std::isfinite(opacity)) {
                if (opacity <= 0.0f) {
                    warnOnce(out, "material '" + m.name + "' says it is fully transparent (opacity 0, an exporter's habit): drawn opaque");
                } else if (opacity < 1.0f) {
                    colour.a *= opacity;
                }
            }
            m.baseColorFactor = glm::vec4(colour.r, colour.g, colour.b, colour.a);
            if (colour.a < 1.0f) m.alphaMode = AlphaMode::Blend;
            int twoSided = 0;
            m.doubleSided = mat->Get(AI_MATKEY_TWOSIDED, twoSided) == AI_SUCCESS && twoSided != 0;
            int shading = 0;
            m.unlit = mat->Get(AI_MATKEY_SHADING_MODEL, shading) == AI_SUCCESS && (shading == aiShadingMode_NoShading || shading == aiShadingMode_Unlit);
            aiString path;
            aiTextureMapMode modes[2] = {aiTextureMapMode_Wrap, aiTextureMapMode_Wrap};   // left as they are when unsaid
            if (mat->GetTexture(aiTextureType_BASE_COLOR, 0, &path, nullptr, nullptr, nullptr, nullptr, modes) == AI_SUCCESS ||
                mat->GetTexture(aiTextureType_DIFFUSE, 0, &path, nullptr, nullptr, nullptr, nullptr, modes) == AI_SUCCESS) {
                const auto wrap = [](aiTextureMapMode mode) {
                    return mode == aiTextureMapMode_Clamp || mode == aiTextureMapMode_Decal ? TextureWrap::Clamp
                           : mode == aiTextureMapMode_Mirror                                  ? TextureWrap::Mirror
                                                                                              : TextureWrap::Repeat;
                };
                const TextureWrap u = wrap(modes[0]), v = wrap(modes[1]);
                const std::string key = std::string(path.C_Str()) + '\n' + char('0' + int(u)) + char('0' + int(v));
                auto it = textureOf.find(key);
                if (it == textureOf.end()) {
                    it = textureOf.emplace(key, readTexture(path.C_Str(), out)).first;
                    out.textures[size_t(it->second)].wrapU = u;
                    out.textures[size_t(it->second)].wrapV = v;
                }
                m.baseColorTexture = it->second;
            }
            out.materials.push_back(std::move(m));
        }
    }

    /// The texture a material names, added to out.textures (white with a warning when it cannot
    /// be found or decoded); its index.
    int readTexture(const std::string& given, ModelData& out) {
        ModelTexture tex;
        tex.name = given;
        std::vector<uint8_t> bytes;
        std::string why = "not found beside the model";
        const aiTexture* embedded = scene_->GetEmbeddedTexture(given.c_str());
        if (embedded && embedded->mHeight > 0) {   // raw texels (BGRA)
            const uint64_t w = embedded->mWidth, h = embedded->mHeight;
            if (w <= kMaxGltfImageSide && h <= kMaxGltfImageSide && embedded->pcData) {
                std::vector<uint8_t> rgba(size_t(w * h * 4));
                for (size_t i = 0; i < size_t(w * h); ++i) {
                    const aiTexel& t = embedded->pcData[i];
                    rgba[4 * i] = t.r, rgba[4 * i + 1] = t.g, rgba[4 * i + 2] = t.b, rgba[4 * i + 3] = t.a;
                }
                tex.width = uint32_t(w), tex.height = uint32_t(h);
                tex.mips = buildMips(rgba.data(), tex.width, tex.height);
            } else {
                why = "an embedded image of " + std::to_string(w) + "x" + std::to_string(h) + " texels";
            }
        } else if (embedded && embedded->pcData) {   // compressed bytes (PNG, JPEG, ...)
            const auto* p = reinterpret_cast<const uint8_t*>(embedded->pcData);
            bytes.assign(p, p + embedded->mWidth);
        } else if (const std::string found = findTexture(given); !found.empty()) {
            if (!readVsi(found, kMaxTextureFileBytes, bytes, why)) why = found + ": " + why;
        }
        if (tex.mips.empty() && !bytes.empty()) decode(bytes, tex, why);
        if (tex.mips.empty()) {
            warnOnce(out, "texture '" + given + "' " + why + ": drawn white");
            tex.width = tex.height = 1;
            tex.mips = {std::vector<uint8_t>{255, 255, 255, 255}};
        }
        out.textures.push_back(std::move(tex));
        return int(out.textures.size()) - 1;
    }

    static void decode(const std::vector<uint8_t>& bytes, ModelTexture& tex, std::string& why) {
        if (bytes.size() > size_t(std::numeric_limits<int>::max())) return;
        // A PNG is walked first (GltfImage.h); other formats (JPEG, TGA, BMP, ...) go to stb with
        // their size checked.
        static constexpr uint8_t kPng[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
        const bool png = bytes.size() >= 8 && std::memcmp(bytes.data(), kPng, 8) == 0;
        if (const std::string bad = png ? checkGltfImageBytes(bytes.data(), bytes.size()) : std::string(); !bad.empty()) {
            why = "cannot be decoded (" + bad + ")";
            return;
        }
        int w = 0, h = 0, comp = 0;
        if (!stbi_info_from_memory(bytes.data(), int(bytes.size()), &w, &h, &comp)) {
            why = std::string("is not an image Orbis decodes (") + stbi_failure_reason() + ")";
            return;
        }
        if (w <= 0 || h <= 0 || w > int(kMaxGltfImageSide) || h > int(kMaxGltfImageSide)) {
            why = "is " + std::to_string(w) + "x" + std::to_string(h) + ", larger than the " + std::to_string(kMaxGltfImageSide) + " pixels a side allowed";
            return;
        }
        unsigned char* data = stbi_load_from_memory(bytes.data(), int(bytes.size()), &w, &h, &comp, 4);
        if (!data) {
            why = std::string("cannot be decoded (") + stbi_failure_reason() + ")";
            return;
        }
        tex.width = uint32_t(w), tex.height = uint32_t(h);
        tex.mips = buildMips(data, tex.width, tex.height);
        stbi_image_free(data);
    }

    /// Where a texture path as the file writes it is: beside the model as given, by its name
    /// alone, then by its name in any case. Empty when nowhere.
    std::string findTexture(std::string given) const {
        std::replace(given.begin(), given.end(), '\\', '/');
        if (given.rfind("file://", 0) == 0) given.erase(0, 7);
        while (given.rfind("./", 0) == 0) given.erase(0, 2);
        const std::string dir = fs::path(modelPath_).parent_path().string();
        const std::string name = fs::path(given).filename().string();
        if (name.empty()) return {};
        std::vector<std::string> candidates;
        if (!given.empty() && given[0] != '/' && given.find(':') == std::string::npos) candidates.push_back(dir + "/" + given);
        candidates.push_back(dir + "/" + name);
        for (const std::string& c : candidates)
            if (vsiSize(c) >= 0) return c;
        // Any case (a file written on Windows names "Texture.JPG" what is "texture.jpg").
        char** entries = VSIReadDir(dir.c_str());
        std::string found;
        for (char** e = entries; e && *e; ++e)
            if (lower(*e) == lower(name)) {
                found = dir + "/" + *e;
                break;
            }
        CSLDestroy(entries);
        return found;
    }

    Result<void> readMeshes(ModelData& out) {
        meshPrimitive_.assign(scene_->mNumMeshes, -1);
        for (unsigned mi = 0; mi < scene_->mNumMeshes; ++mi) {
            const aiMesh* mesh = scene_->mMeshes[mi];
            const std::string label = std::string("mesh '") + mesh->mName.C_Str() + "'";
            if (!(mesh->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) {
                warnOnce(out, "points and lines are not drawn (" + label + ")");
                continue;
            }
            if (out.vertices.size() + mesh->mNumVertices > kMaxGltfVertices)
                return makeError(file_ + ": more than " + std::to_string(kMaxGltfVertices) + " vertices (at " + label + ")");
            if (out.indices.size() + uint64_t(mesh->mNumFaces) * 3 > kMaxGltfIndices)
                return makeError(file_ + ": more than " + std::to_string(kMaxGltfIndices) + " indices (at " + label + ")");
            ModelPrimitive p;
            p.vertexOffset = int32_t(out.vertices.size());
            p.vertexCount = mesh->mNumVertices;
            p.firstIndex = uint32_t(out.indices.size());
            p.material = mesh->mMaterialIndex < out.materials.size() ? int(mesh->mMaterialIndex) : -1;
            for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
                ModelVertex x{};
                const aiVector3D& q = mesh->mVertices[v];
                x.position[0] = q.x, x.position[1] = q.y, x.position[2] = q.z;
                const aiVector3D n = mesh->mNormals ? mesh->mNormals[v] : aiVector3D(0.0f, 1.0f, 0.0f);
                const bool finite = std::isfinite(n.x) && std::isfinite(n.y) && std::isfinite(n.z);
                x.normal[0] = finite ? n.x : 0.0f, x.normal[1] = finite ? n.y : 1.0f, x.normal[2] = finite ? n.z : 0.0f;
                if (mesh->mTextureCoords[0]) x.uv[0] = mesh->mTextureCoords[0][v].x, x.uv[1] = mesh->mTextureCoords[0][v].y;
                x.color = mesh->mColors[0] ? packColor(mesh->mColors[0][v]) : 0xFFFFFFFFu;
                out.vertices.push_back(x);
            }
            for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
                const aiFace& face = mesh->mFaces[f];
                if (face.mNumIndices != 3) continue;   // (points and lines of a mixed mesh)
                for (int k = 0; k < 3; ++k) out.indices.push_back(face.mIndices[k]);
            }
            p.indexCount = uint32_t(out.indices.size()) - p.firstIndex;
            if (p.indexCount == 0) continue;
            meshPrimitive_[mi] = int(out.primitives.size());
            out.primitives.push_back(p);
        }
        return {};
    }

    Result<void> walk(const aiNode* node, const glm::dmat4& parent, int depth, ModelData& out) {
        if (depth > kMaxDepth) return makeError(file_ + ": the node hierarchy is deeper than " + std::to_string(kMaxDepth));
        const glm::dmat4 world = parent * toGlm(node->mTransformation);
        const bool mirrored = glm::determinant(glm::dmat3(world)) < 0.0;
        for (unsigned i = 0; i < node->mNumMeshes; ++i) {
            const unsigned mi = node->mMeshes[i];
            if (mi >= meshPrimitive_.size() || meshPrimitive_[mi] < 0) continue;
            if (out.draws.size() >= 1'000'000) return makeError(file_ + ": more than a million drawn meshes");
            const uint32_t prim = uint32_t(meshPrimitive_[mi]);
            const ModelPrimitive& p = out.primitives[prim];
            out.draws.push_back({prim, glm::mat4(world), mirrored, -1, -1});
            drawNodes_.push_back(node);
            out.triangles += p.indexCount / 3;
            for (uint32_t v = 0; v < p.vertexCount; ++v) {
                const ModelVertex& x = out.vertices[size_t(p.vertexOffset) + v];
                const glm::dvec3 q = glm::dvec3(world * glm::dvec4(x.position[0], x.position[1], x.position[2], 1.0));
                out.boundsMin = glm::min(out.boundsMin, q);
                out.boundsMax = glm::max(out.boundsMax, q);
            }
        }
        for (unsigned c = 0; c < node->mNumChildren; ++c)
            if (auto r = walk(node->mChildren[c], world, depth + 1, out); !r) return r;
        return {};
    }

    /// The file's node animations (rigid: translation, rotation, scale keys of its nodes) as a
    /// rig: a node for the axes and units, then the file's nodes with their rest transforms;
    /// each draw moved by its node. Keys at a time not after the one before are left out (glTF
    /// needs increasing times); mesh and morph animations are not read (a warning).
    Result<void> readAnimations(ModelData& out) {
        ModelRig rig;
        std::map<const aiNode*, uint32_t> index;
        std::map<std::string, uint32_t> byName;
        RigNode axes;
        axes.name = "(axes and units)";
        axes.hasMatrix = true;
        axes.matrix = rootTransform();
        rig.nodes.push_back(axes);
        rig.order.push_back(0);
        // Depth first, parents before children (the walk bounded the depth).
        std::vector<std::pair<const aiNode*, uint32_t>> stack{{scene_->mRootNode, 0u}};
        while (!stack.empty()) {
            const auto [node, parent] = stack.back();
            stack.pop_back();
            if (rig.nodes.size() >= kMaxAnimatedNodes) return makeError(file_ + ": more than " + std::to_string(kMaxAnimatedNodes) + " nodes to animate");
            RigNode n;
            n.name = node->mName.C_Str();
            n.parent = int(parent);
            aiVector3D s, t;
            aiQuaternion r;
            node->mTransformation.Decompose(s, r, t);
            n.translation = glm::dvec3(t.x, t.y, t.z);
            n.rotation = glm::normalize(glm::dquat(r.w, r.x, r.y, r.z));
            n.scale = glm::dvec3(s.x, s.y, s.z);
            // A transform with shear is not a TRS: kept as a matrix (not animatable, as in glTF).
            const glm::dmat4 rebuilt = glm::translate(glm::dmat4(1.0), n.translation) * glm::mat4_cast(n.rotation) * glm::scale(glm::dmat4(1.0), n.scale);
            const glm::dmat4 given = toGlm(node->mTransformation);
            double off = 0.0, size = 1e-9;
            for (int c = 0; c < 4; ++c)
                for (int k = 0; k < 4; ++k) off = std::max(off, std::abs(rebuilt[c][k] - given[c][k])), size = std::max(size, std::abs(given[c][k]));
            if (!(off <= 1e-5 * size)) {
                n.hasMatrix = true;
                n.matrix = given;
            }
            const uint32_t i = uint32_t(rig.nodes.size());
            index[node] = i;
            byName.emplace(n.name, i);   // the first of a name
            rig.nodes.push_back(std::move(n));
            rig.order.push_back(i);
            for (unsigned c = node->mNumChildren; c-- > 0;) stack.push_back({node->mChildren[c], i});
        }
        uint64_t keyframes = 0;
        bool skipped = false;
        for (unsigned a = 0; a < scene_->mNumAnimations; ++a) {
            const aiAnimation* anim = scene_->mAnimations[a];
            const double ticks = anim->mTicksPerSecond > 0.0 ? anim->mTicksPerSecond : 25.0;   // Assimp's default
            ModelAnimation m;
            m.name = anim->mName.length ? anim->mName.C_Str() : "animation " + std::to_string(a);
            skipped |= anim->mNumMeshChannels > 0 || anim->mNumMorphMeshChannels > 0;
            for (unsigned c = 0; c < anim->mNumChannels; ++c) {
                const aiNodeAnim* ch = anim->mChannels[c];
                const auto node = byName.find(ch->mNodeName.C_Str());
                if (node == byName.end() || rig.nodes[node->second].hasMatrix) {
                    skipped = true;
                    continue;
                }
                // One sampler from a key array: seconds and values, increasing times only.
                const auto add = [&](AnimationPath path, unsigned count, uint32_t components, auto timeOf, auto valuesOf) {
                    AnimationSampler sampler;
                    sampler.components = components;
                    for (unsigned k = 0; k < count; ++k) {
                        const double t = timeOf(k) / ticks;
                        if (!std::isfinite(t) || (!sampler.times.empty() && t <= double(sampler.times.back()))) continue;
                        sampler.times.push_back(float(t));
                        valuesOf(k, sampler.values);
                    }
                    if (sampler.times.empty()) return;
                    keyframes += sampler.times.size();
                    m.duration = std::max(m.duration, double(sampler.times.back()));
                    m.channels.push_back({node->second, path, uint32_t(m.samplers.size())});
                    m.samplers.push_back(std::move(sampler));
                };
                add(AnimationPath::Translation, ch->mNumPositionKeys, 3, [&](unsigned k) { return ch->mPositionKeys[k].mTime; },
                    [&](unsigned k, std::vector<float>& v) {
                        const aiVector3D& p = ch->mPositionKeys[k].mValue;
                        v.insert(v.end(), {p.x, p.y, p.z});
                    });
                add(AnimationPath::Rotation, ch->mNumRotationKeys, 4, [&](unsigned k) { return ch->mRotationKeys[k].mTime; },
                    [&](unsigned k, std::vector<float>& v) {
                        const aiQuaternion& q = ch->mRotationKeys[k].mValue;
                        v.insert(v.end(), {q.x, q.y, q.z, q.w});
                    });
                add(AnimationPath::Scale, ch->mNumScalingKeys, 3, [&](unsigned k) { return ch->mScalingKeys[k].mTime; },
                    [&](unsigned k, std::vector<float>& v) {
                        const aiVector3D& p = ch->mScalingKeys[k].mValue;
                        v.insert(v.end(), {p.x, p.y, p.z});
                    });
                if (keyframes > kMaxGltfKeyframes)
                    return makeError(file_ + ": its animations have more than " + std::to_string(kMaxGltfKeyframes) + " keyframes");
            }
            if (!m.channels.empty()) rig.animations.push_back(std::move(m));
        }
        if (skipped) warnOnce(out, "some of its animations are not read (mesh or morph animations, or nodes given as matrices with shear)");
        // Only what moves a drawn node counts (a skeleton's bones move nothing while skins are
        // not read): otherwise the model keeps the fast, unposed path.
        std::vector<bool> carries(rig.nodes.size(), false);   // a draw's node or one above it
        for (const aiNode* n : drawNodes_)
            for (int i = int(index.at(n)); i >= 0 && !carries[size_t(i)]; i = rig.nodes[size_t(i)].parent) carries[size_t(i)] = true;
        bool moves = false;
        for (const ModelAnimation& a : rig.animations)
            for (const AnimationChannel& c : a.channels) moves |= carries[c.node];
        if (!moves) {
            warnOnce(out, "its animations move no node that draws (a skeleton's, whose skins are not read): the rest pose is drawn");
            return {};
        }
        for (size_t d = 0; d < out.draws.size(); ++d) out.draws[d].node = int(index.at(drawNodes_[d]));
        out.rig = std::move(rig);
        posedBounds(out);
        return {};
    }

    const std::string file_;        // for messages
    const std::string modelPath_;   // what Assimp reads (a /vsizip/ path inside a KMZ)
    const MeshImportOptions& options_;
    const aiScene* scene_ = nullptr;
    std::vector<int> meshPrimitive_;
    std::vector<const aiNode*> drawNodes_;   // each draw's node
    std::set<std::string> warned_;
};

/// The COLLADA model a KMZ's KML links (its first <Model>'s <Link><href>), as a /vsizip/ path.
Result<std::string> kmzModel(const std::string& kmz) {
    const std::string root = "/vsizip/" + kmz;
    char** entries = VSIReadDirRecursive(root.c_str());
    std::vector<std::string> files;
    for (char** e = entries; e && *e; ++e) files.emplace_back(*e);
    CSLDestroy(entries);
    if (files.empty()) return makeError(kmz + ": not a KMZ (a zip archive) or an empty one");
    std::string kml;
    for (const std::string& f : files)
        if (lower(fs::path(f).extension().string()) == ".kml" && (kml.empty() || lower(f) == "doc.kml")) kml = f;
    std::string href;
    bool fromKml = false;
    if (!kml.empty()) {
        std::vector<uint8_t> bytes;
        std::string why;
        if (!readVsi(root + "/" + kml, uint64_t(16) << 20, bytes, why)) return makeError(kmz + ": " + kml + ": " + why);
        href = kmlModelHref(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
        fromKml = !href.empty();
    }
    if (href.empty()) {   // no KML or no <Model>: the archive's only COLLADA file
        for (const std::string& f : files)
            if (lower(fs::path(f).extension().string()) == ".dae") {
                if (!href.empty()) return makeError(kmz + ": its KML links no <Model> and it holds several COLLADA files");
                href = f;
            }
        if (href.empty()) return makeError(kmz + ": holds no 3-D model (no <Model> in its KML, no .dae file)");
    }
    if (href.find("://") != std::string::npos) return makeError(kmz + ": its model is outside the archive (" + href + "): Orbis reads models inside it");
    const fs::path inside = ((fromKml ? fs::path(kml).parent_path() : fs::path()) / href).lexically_normal();
    if (inside.empty() || *inside.begin() == "..") return makeError(kmz + ": its model's path " + href + " leads outside the archive");
    return root + "/" + inside.generic_string();
}

}  // namespace

bool isMeshFormat(const std::string& path) {
    static const std::set<std::string> kFormats = {".obj", ".fbx", ".dae", ".kmz", ".3ds", ".ply", ".stl"};
    return kFormats.count(lower(fs::path(path).extension().string())) > 0;
}

Result<ModelData> loadMesh(const std::string& path, const MeshImportOptions& options) {
    if (options.up && *options.up != 'y' && *options.up != 'z') return makeError(path + ": the up axis is 'y' or 'z'");
    if (options.unitMetres && !(std::isfinite(*options.unitMetres) && *options.unitMetres > 0.0))
        return makeError(path + ": the unit must be a positive number of metres");
    std::error_code ec;
    const auto size = fs::file_size(path, ec);
    if (ec) return makeError(path + ": cannot read (" + ec.message() + ")");
    if (size > kMaxGltfFileBytes)
        return makeError(path + ": " + std::to_string(size >> 20) + " MiB is more than the " + std::to_string(kMaxGltfFileBytes >> 20) + " MiB a model may have");
    std::string model = fs::absolute(path).string();
    if (lower(fs::path(path).extension().string()) == ".kmz") {
        auto inside = kmzModel(model);
        if (!inside) return inside.error();
        model = *inside;
    }
    return Reader(path, model, options).read();
}

}  // namespace orbis::models
