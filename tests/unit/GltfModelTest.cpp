// glTF 2.0 reading: the real sample models, external files, the axis convention, and broken
// inputs that must give clear errors.
#include "layers/models/GltfModel.h"
#include "formats/motion/Attitude.h"

#include <gtest/gtest.h>
#include <stb_image_write.h>
#include <zlib.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <unistd.h>

namespace fs = std::filesystem;
using namespace orbis::models;

namespace {

const fs::path kModels = fs::path(ORBIS_SHARED_DATA_DIR) / "models";

#define REQUIRE_SHARED(p) \
    if (!fs::exists(p)) GTEST_SKIP() << "shared data absent: " << (p)

fs::path tempDir(const char* name) {
    const fs::path d = fs::temp_directory_path() / ("orbis-gltf-" + std::to_string(::getpid()) + "-" + name);
    fs::create_directories(d);
    return d;
}

void writeFile(const fs::path& p, const std::string& text) {
    std::ofstream(p, std::ios::binary) << text;
}

// One triangle in an external .bin, with a texture in an external .png.
std::string triangleGltf(const std::string& bin, const std::string& png, const std::string& extra = "") {
    return R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],
      "nodes":[{"mesh":0,"translation":[10,0,0]}],
      "meshes":[{"name":"tri","primitives":[{"attributes":{"POSITION":0,"TEXCOORD_0":1},"material":0}]}],
      "materials":[{"name":"red","pbrMetallicRoughness":{"baseColorFactor":[1,0,0,1],"baseColorTexture":{"index":0}},"alphaMode":"MASK","alphaCutoff":0.25,"doubleSided":true}],
      "textures":[{"source":0}],"images":[{"uri":")" + png + R"("}],
      "buffers":[{"uri":")" + bin + R"(","byteLength":60}],
      "bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":36},{"buffer":0,"byteOffset":36,"byteLength":24}],
      "accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]},
                   {"bufferView":1,"componentType":5126,"count":3,"type":"VEC2"}])" + extra + "}";
}

void replaceOnce(std::string& s, const std::string& from, const std::string& to) {
    const size_t at = s.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    s.replace(at, from.size(), to);
}

void writeTriangleFiles(const fs::path& dir) {
    const float data[15] = {0, 0, 0, 1, 0, 0, 0, 1, 0, /*uv*/ 0, 0, 1, 0, 0, 1};
    std::ofstream(dir / "tri.bin", std::ios::binary).write(reinterpret_cast<const char*>(data), sizeof(data));
    const uint8_t px[2 * 2 * 4] = {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255, 255, 255, 255};
    ASSERT_TRUE(stbi_write_png((dir / "tex.png").c_str(), 2, 2, 4, px, 8));
}

}  // namespace

TEST(GltfModel, BoxTexturedBinary) {
    REQUIRE_SHARED(kModels / "BoxTextured.glb");
    auto m = loadGltf((kModels / "BoxTextured.glb").string());
    ASSERT_TRUE(m) << m.message();
    EXPECT_EQ(m->vertices.size(), 24u);
    EXPECT_EQ(m->indices.size(), 36u);
    EXPECT_EQ(m->triangles, 12u);
    ASSERT_EQ(m->draws.size(), 1u);
    ASSERT_EQ(m->materials.size(), 1u);
    ASSERT_EQ(m->textures.size(), 1u);
    EXPECT_EQ(m->materials[0].baseColorTexture, 0);
    EXPECT_GT(m->textures[0].width, 1u);
    EXPECT_EQ(m->textures[0].mips.size(), size_t(std::bit_width(std::max(m->textures[0].width, m->textures[0].height))));
    // A unit cube about the origin (its node turns COLLADA's Z up into glTF's Y up).
    for (int a = 0; a < 3; ++a) {
        EXPECT_NEAR(m->boundsMin[a], -0.5, 1e-6);
        EXPECT_NEAR(m->boundsMax[a], 0.5, 1e-6);
    }
    EXPECT_TRUE(m->warnings.empty());
}

TEST(GltfModel, EmbeddedGltfEqualsBinary) {
    REQUIRE_SHARED(kModels / "BoxTextured_embedded.gltf");
    auto a = loadGltf((kModels / "BoxTextured.glb").string());
    auto b = loadGltf((kModels / "BoxTextured_embedded.gltf").string());
    ASSERT_TRUE(a) << a.message();
    ASSERT_TRUE(b) << b.message();
    ASSERT_EQ(a->vertices.size(), b->vertices.size());
    EXPECT_EQ(0, std::memcmp(a->vertices.data(), b->vertices.data(), a->vertices.size() * sizeof(ModelVertex)));
    EXPECT_EQ(a->indices, b->indices);
    EXPECT_EQ(a->textures[0].mips[0], b->textures[0].mips[0]);
}

TEST(GltfModel, NodeHierarchyOfTheEngine) {
    REQUIRE_SHARED(kModels / "2CylinderEngine.glb");
    auto m = loadGltf((kModels / "2CylinderEngine.glb").string());
    ASSERT_TRUE(m) << m.message();
    // 29 meshes, some used by several nodes: more draws than meshes, each with its own transform.
    EXPECT_GE(m->draws.size(), 29u);
    std::set<std::vector<float>> transforms;
    for (const auto& d : m->draws) {
        const float* f = &d.transform[0][0];
        transforms.insert(std::vector<float>(f, f + 16));
    }
    EXPECT_GT(transforms.size(), 10u);
    EXPECT_GT(m->triangles, 10000u);
    // The engine is about 0.8 x 0.4 x 0.6 units big: bounds come from transformed vertices.
    EXPECT_GT(m->radius(), 100.0);   // millimetres in this file
    EXPECT_LT(m->radius(), 2000.0);
}

TEST(GltfModel, ExternalBufferWithMorphTargetsAndAnimation) {
    REQUIRE_SHARED(kModels / "AnimatedMorphCube" / "AnimatedMorphCube.gltf");
    auto m = loadGltf((kModels / "AnimatedMorphCube" / "AnimatedMorphCube.gltf").string());
    ASSERT_TRUE(m) << m.message();
    EXPECT_EQ(m->triangles, 12u);
    // The node scales the 2 cm cube by 100; the bounds hold every pose of its animation, in
    // which the targets pull the top up by up to 2 cm (2 m scaled) and slant it.
    EXPECT_GT(m->radius(), std::sqrt(3.0) * 1.0);
    EXPECT_LT(m->radius(), 3.0);
    // Morph targets and the animation are read (GltfAnimationTest checks them): nothing is left out.
    EXPECT_TRUE(m->animated());
    EXPECT_EQ(m->rig.animations.size(), 1u);
    EXPECT_TRUE(m->warnings.empty()) << m->warnings.front();
}

TEST(GltfModel, ExternalFilesMaterialAndFlatNormals) {
    const fs::path dir = tempDir("external");
    writeTriangleFiles(dir);
    writeFile(dir / "tri.gltf", triangleGltf("tri.bin", "tex.png"));
    auto m = loadGltf((dir / "tri.gltf").string());
    ASSERT_TRUE(m) << m.message();
    ASSERT_EQ(m->vertices.size(), 3u);
    // No normals in the file: the face normal (+Z for this counter-clockwise triangle).
    for (const auto& v : m->vertices) {
        EXPECT_FLOAT_EQ(v.normal[2], 1.0f);
        EXPECT_EQ(v.color, 0xffffffffu);
    }
    EXPECT_FLOAT_EQ(m->vertices[1].uv[0], 1.0f);
    ASSERT_EQ(m->materials.size(), 1u);
    const ModelMaterial& mat = m->materials[0];
    EXPECT_EQ(mat.baseColorFactor, glm::vec4(1, 0, 0, 1));
    EXPECT_EQ(mat.alphaMode, AlphaMode::Mask);
    EXPECT_FLOAT_EQ(mat.alphaCutoff, 0.25f);
    EXPECT_TRUE(mat.doubleSided);
    ASSERT_EQ(m->textures.size(), 1u);
    EXPECT_EQ(m->textures[0].width, 2u);
    EXPECT_EQ(m->textures[0].mips.size(), 2u);
    EXPECT_EQ(m->textures[0].mips[0][0], 255);
    // The node's translation is in the draw and the bounds.
    EXPECT_FLOAT_EQ(m->draws[0].transform[3][0], 10.0f);
    EXPECT_DOUBLE_EQ(m->boundsMin.x, 10.0);
    EXPECT_DOUBLE_EQ(m->boundsMax.x, 11.0);
    fs::remove_all(dir);
}

TEST(GltfModel, AxesOntoTheBody) {
    const glm::dmat3 r = gltfToBody();
    EXPECT_EQ(r * glm::dvec3(0, 0, 1), glm::dvec3(1, 0, 0));    // front (+Z) -> forward
    EXPECT_EQ(r * glm::dvec3(0, 1, 0), glm::dvec3(0, 0, -1));   // up (+Y) -> -down
    EXPECT_EQ(r * glm::dvec3(-1, 0, 0), glm::dvec3(0, 1, 0));   // right (-X) -> right
    EXPECT_DOUBLE_EQ(glm::determinant(r), 1.0);                  // a rotation, not a mirror
    EXPECT_EQ(r, orbis::motion::gltfToBody()) << "one convention, written in formats/motion/Attitude.h";
}

TEST(GltfModel, MipChainAverages) {
    const uint8_t px[3 * 1 * 4] = {0, 0, 0, 255, 100, 100, 100, 255, 200, 200, 200, 255};
    auto mips = buildMips(px, 3, 1);
    ASSERT_EQ(mips.size(), 2u);
    ASSERT_EQ(mips[1].size(), 4u);
    EXPECT_EQ(mips[1][0], 50);   // texels 0 and 1; the odd third falls off the 1-wide level
    EXPECT_EQ(mips[1][3], 255);
}

TEST(GltfModel, BrokenInputsGiveClearErrors) {
    const fs::path dir = tempDir("broken");
    writeTriangleFiles(dir);
    auto expectError = [&](const std::string& name, const std::string& text, const std::string& needle) {
        writeFile(dir / name, text);
        auto m = loadGltf((dir / name).string());
        ASSERT_FALSE(m) << name;
        EXPECT_NE(m.message().find(name), std::string::npos) << m.message();
        EXPECT_NE(m.message().find(needle), std::string::npos) << name << ": " << m.message();
    };
    expectError("notjson.gltf", "{ this is not json", "not a readable glTF");
    expectError("missingbin.gltf", triangleGltf("nothere.bin", "tex.png"), "not a readable glTF");
    expectError("draco.gltf", triangleGltf("tri.bin", "tex.png", R"(,"extensionsRequired":["KHR_draco_mesh_compression"],"extensionsUsed":["KHR_draco_mesh_compression"])"),
                "KHR_draco_mesh_compression");
    // An accessor that claims more vertices than its buffer view holds.
    std::string past = triangleGltf("tri.bin", "tex.png");
    replaceOnce(past, R"("count":3,"type":"VEC3")", R"("count":9,"type":"VEC3")");
    expectError("past.gltf", past, "run past");
    // Indices pointing past the vertices.
    const uint16_t badIdx[4] = {0, 1, 7, 0};
    std::ofstream(dir / "idx.bin", std::ios::binary).write(reinterpret_cast<const char*>(badIdx), sizeof(badIdx));
    std::string idx = triangleGltf("tri.bin", "tex.png");
    replaceOnce(idx, R"("material":0)", R"("material":0,"indices":2)");
    replaceOnce(idx, R"({"uri":"tri.bin","byteLength":60})", R"({"uri":"tri.bin","byteLength":60},{"uri":"idx.bin","byteLength":8})");
    replaceOnce(idx, R"("byteLength":24}])", R"("byteLength":24},{"buffer":1,"byteOffset":0,"byteLength":6}])");
    replaceOnce(idx, R"("type":"VEC2"}])", R"("type":"VEC2"},{"bufferView":2,"componentType":5123,"count":3,"type":"SCALAR"}])");
    expectError("badindex.gltf", idx, "index 7");
    // A truncated binary file.
    REQUIRE_SHARED(kModels / "BoxTextured.glb");
    std::ifstream in(kModels / "BoxTextured.glb", std::ios::binary);
    std::string glb((std::istreambuf_iterator<char>(in)), {});
    expectError("cut.glb", glb.substr(0, glb.size() / 2), "not a readable glTF");
    fs::remove_all(dir);
}

TEST(GltfModel, HugeImageIsRefusedBeforeDecoding) {
    const fs::path dir = tempDir("huge");
    writeTriangleFiles(dir);
    // A 2x2 PNG whose header is patched to claim 9000 x 9000 pixels (stb itself refuses more
    // than 2^30 bytes, so this is the case only our limit catches).
    std::ifstream in(dir / "tex.png", std::ios::binary);
    std::string png((std::istreambuf_iterator<char>(in)), {});
    ASSERT_GT(png.size(), 24u);
    const uint8_t side[4] = {0, 0, 0x23, 0x28};   // 9000, big-endian, at IHDR width and height
    std::memcpy(&png[16], side, 4);
    std::memcpy(&png[20], side, 4);
    writeFile(dir / "huge.png", png);
    writeFile(dir / "huge.gltf", triangleGltf("tri.bin", "huge.png"));
    auto m = loadGltf((dir / "huge.gltf").string());
    ASSERT_FALSE(m);
    EXPECT_NE(m.message().find("9000x9000"), std::string::npos) << m.message();
    fs::remove_all(dir);
}

// Found by mutating real files (../shared/data/bad/README.md): an image in a bufferView whose
// offset lies past its buffer. tinygltf hands the pointer on unchecked; stb read wild memory.
TEST(GltfModel, ImageViewPastItsBufferIsRefused) {
    const fs::path dir = tempDir("imageview");
    writeTriangleFiles(dir);
    // Far past the 60-byte buffer, past 2^32, and starting inside it but running 47 bytes past.
    for (const char* offset : {"100000", "4294967296", "40"}) {
        std::string text = triangleGltf("tri.bin", "tex.png");
        replaceOnce(text, R"("images":[{"uri":"tex.png"}])", R"("images":[{"bufferView":2,"mimeType":"image/png"}])");
        replaceOnce(text, R"("byteLength":24}])", std::string(R"("byteLength":24},{"buffer":0,"byteOffset":)") + offset + R"(,"byteLength":67}])");
        const std::string name = std::string("view-") + offset + ".gltf";
        writeFile(dir / name, text);
        auto m = loadGltf((dir / name).string());
        ASSERT_FALSE(m) << name;
        EXPECT_NE(m.message().find(name), std::string::npos) << m.message();
        EXPECT_NE(m.message().find("image 0: its bufferView lies outside its buffer"), std::string::npos) << m.message();
    }
    fs::remove_all(dir);
    for (const char* bad : {"glb-image-view-offset-100000.glb", "glb-image-view-offset-4294967296.glb"}) {
        const fs::path p = fs::path(ORBIS_SHARED_DATA_DIR) / "bad" / bad;
        REQUIRE_SHARED(p);
        auto m = loadGltf(p.string());
        ASSERT_FALSE(m) << bad;
        EXPECT_NE(m.message().find(bad), std::string::npos) << m.message();
        EXPECT_NE(m.message().find("image 0: its bufferView lies outside its buffer"), std::string::npos) << m.message();
    }
}

namespace {

void appendChunk(std::string& png, const char* type, const std::string& data) {
    const auto be32 = [&](uint32_t v) {
        for (int i = 3; i >= 0; --i) png += char(uint8_t(v >> (8 * i)));
    };
    be32(uint32_t(data.size()));
    const std::string typed = std::string(type, 4) + data;
    png += typed;
    be32(uint32_t(crc32(0, reinterpret_cast<const Bytef*>(typed.data()), uInt(typed.size()))));
}

/// A PNG whose header says 2x2 RGBA and whose image data is `raw` compressed.
std::string pngOf(const std::string& raw) {
    std::string png("\x89PNG\r\n\x1a\n", 8);
    appendChunk(png, "IHDR", std::string("\0\0\0\2\0\0\0\2\x08\x06\0\0\0", 13));
    std::string z(compressBound(uLong(raw.size())), '\0');
    uLongf n = uLongf(z.size());
    EXPECT_EQ(compress2(reinterpret_cast<Bytef*>(z.data()), &n, reinterpret_cast<const Bytef*>(raw.data()), uLong(raw.size()), 9), Z_OK);
    z.resize(n);
    appendChunk(png, "IDAT", z);
    appendChunk(png, "IEND", "");
    return png;
}

}  // namespace

// Found by the fuzzer (tests/fuzz/seeds/gltf/oom-png-chunk-length.glb): stb trusts a PNG's
// chunk lengths and inflates for as long as the data goes on, so a 1 KiB image asked for
// 1.9 GB. A PNG is walked first; glTF's images are PNG or JPEG, nothing else reaches stb.
TEST(GltfModel, ImagesThatAskForMoreThanTheyHoldAreRefused) {
    const fs::path dir = tempDir("png-bounds");
    writeTriangleFiles(dir);
    const std::string good = pngOf(std::string(2 * 9, '\0'));   // two rows: a filter byte and 2 RGBA pixels
    writeFile(dir / "good.png", good);
    writeFile(dir / "good.gltf", triangleGltf("tri.bin", "good.png"));
    auto ok = loadGltf((dir / "good.gltf").string());
    ASSERT_TRUE(ok) << ok.message();

    std::string longChunk = good;
    const uint8_t huge[4] = {0x7f, 0xff, 0xff, 0xf0};
    std::memcpy(&longChunk[33], huge, 4);   // the IDAT chunk's length, after the 8-byte signature and IHDR's 25
    const std::pair<std::string, std::string> cases[] = {
        {longChunk, "a PNG chunk runs past the end of the data"},
        {pngOf(std::string(10 << 20, '\0')), "a PNG's image data inflates past the size its header gives"},
        {std::string("BM") + std::string(60, '\0'), "not a PNG or JPEG"},
    };
    int i = 0;
    for (const auto& [bytes, why] : cases) {
        const std::string name = "bad" + std::to_string(i++);
        writeFile(dir / (name + ".png"), bytes);
        writeFile(dir / (name + ".gltf"), triangleGltf("tri.bin", name + ".png"));
        auto m = loadGltf((dir / (name + ".gltf")).string());
        ASSERT_FALSE(m) << name;
        EXPECT_NE(m.message().find(name + ".gltf"), std::string::npos) << m.message();
        EXPECT_NE(m.message().find("image 0: " + why), std::string::npos) << m.message();
    }
    fs::remove_all(dir);
    const fs::path found = fs::path(ORBIS_SOURCE_DIR) / "tests/fuzz/seeds/gltf/oom-png-chunk-length.glb";
    auto m = loadGltf(found.string());
    ASSERT_FALSE(m);
    EXPECT_NE(m.message().find("image 0: a PNG chunk runs past the end of the data"), std::string::npos) << m.message();
}

TEST(GltfModel, MissingFile) {
    auto m = loadGltf("/nonexistent/model.glb");
    ASSERT_FALSE(m);
    EXPECT_NE(m.message().find("/nonexistent/model.glb"), std::string::npos);
}
