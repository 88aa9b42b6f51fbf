// Models in mesh formats through Assimp (MeshModel.h): the same model written as OBJ, PLY and
// STL reads the same; FBX's centimetres and axis settings, 3DS's Z up and a scene's override
// land models upright at true scale; textures found as Windows exporters write their paths, or
// named in a warning and drawn white; a KMZ's COLLADA model read from inside the archive; hostile
// files (a PLY claiming 4e9 vertices, a COLLADA node graph that instantiates itself or expands
// without bound, truncated files) refused with clear errors. The real files come from Debian's
// assimp-testmodels; tests that need them skip without it.
#include "base/Png.h"
#include "layers/models/GltfAnimation.h"
#include "layers/models/MeshChecks.h"
#include "layers/models/MeshModel.h"
#include "tests/support/ProcessTempDir.h"
#include "tests/unit/GltfTestFiles.h"

#include <cpl_vsi.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace orbis::models {
namespace {

namespace fs = std::filesystem;

const fs::path kModels = "/usr/share/assimp/models";

#define NEED_TESTMODELS() \
    if (!fs::exists(kModels / "OBJ" / "WusonOBJ.obj")) GTEST_SKIP() << "assimp-testmodels is not installed"

glm::dvec3 extent(const ModelData& m) { return m.boundsMax - m.boundsMin; }

bool warned(const ModelData& m, const std::string& text) {
    for (const std::string& w : m.warnings)
        if (w.find(text) != std::string::npos) return true;
    return false;
}

TEST(MeshModel, OneModelReadsTheSameAsObjPlyAndStl) {
    NEED_TESTMODELS();
    auto obj = loadMesh((kModels / "OBJ" / "WusonOBJ.obj").string());
    ASSERT_TRUE(obj.ok()) << obj.message();
    for (const fs::path& p : {kModels / "PLY" / "Wuson.ply", kModels / "STL" / "Wuson.stl"}) {
        SCOPED_TRACE(p.string());
        auto m = loadMesh(p.string());
        ASSERT_TRUE(m.ok()) << m.message();
        EXPECT_EQ(m->triangles, obj->triangles);
        for (int a = 0; a < 3; ++a) {
            EXPECT_NEAR(m->boundsMin[a], obj->boundsMin[a], 1e-4);
            EXPECT_NEAR(m->boundsMax[a], obj->boundsMax[a], 1e-4);
        }
    }
    // Upright: the figure stands on y = 0, 1.5 units tall.
    EXPECT_NEAR(obj->boundsMin.y, 0.0, 1e-3);
    EXPECT_NEAR(extent(*obj).y, 1.516, 1e-3);
    EXPECT_FALSE(obj->vertices.empty());
    EXPECT_FALSE(obj->animated());
}

TEST(MeshModel, FbxCentimetresAndAxesGiveTheObjTwinsSize) {
    NEED_TESTMODELS();
    // spider.fbx is spider.obj exported by Blender in centimetres (UnitScaleFactor 1): 100 times
    // the numbers, the same size in metres (the OBJ's units taken as metres).
    auto fbx = loadMesh((kModels / "FBX" / "spider.fbx").string());
    auto obj = loadMesh((kModels / "OBJ" / "spider.obj").string());
    ASSERT_TRUE(fbx.ok()) << fbx.message();
    ASSERT_TRUE(obj.ok()) << obj.message();
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(extent(*fbx)[a], extent(*obj)[a], 1e-3 * extent(*obj)[a]) << a;
    // The scene's unit overrides the file's.
    MeshImportOptions metres;
    metres.unitMetres = 1.0;
    auto raw = loadMesh((kModels / "FBX" / "spider.fbx").string(), metres);
    ASSERT_TRUE(raw.ok());
    EXPECT_NEAR(extent(*raw).x, 100.0 * extent(*obj).x, 0.1 * extent(*obj).x);
    // A file of 5 m units (UnitScaleFactor 500).
    auto five = loadMesh((kModels / "FBX" / "global_settings.fbx").string());
    auto fiveRaw = loadMesh((kModels / "FBX" / "global_settings.fbx").string(), metres);
    ASSERT_TRUE(five.ok() && fiveRaw.ok());
    EXPECT_NEAR(extent(*five).y, 5.0 * extent(*fiveRaw).y, 1e-6 * extent(*five).y);
}

TEST(MeshModel, ZUpFilesStandUpright) {
    // A Z-up CAD export: a 1 x 2 x 10 column along +Z, in millimetres.
    const fs::path dir = test::processTempDir("orbis-mesh-zup");
    {
        std::ofstream f(dir / "column.obj");
        f << "v 0 0 0\nv 1000 0 0\nv 1000 2000 0\nv 0 2000 0\nv 0 0 10000\nv 1000 0 10000\nv 1000 2000 10000\nv 0 2000 10000\n"
             "f 1 2 3 4\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";
    }
    MeshImportOptions cad;
    cad.up = 'z';
    cad.unitMetres = 0.001;
    auto m = loadMesh((dir / "column.obj").string(), cad);
    ASSERT_TRUE(m.ok()) << m.message();
    EXPECT_NEAR(extent(*m).y, 10.0, 1e-9);   // up
    EXPECT_NEAR(extent(*m).x, 1.0, 1e-9);
    EXPECT_NEAR(extent(*m).z, 2.0, 1e-9);
    EXPECT_NEAR(m->boundsMax.z, 0.0, 1e-9);   // file +Y (away from a front view) is glTF -Z
    EXPECT_EQ(m->triangles, 12u);
    // Without the override it lies along y... no: OBJ is taken as +Y up, so the column lies along z.
    auto lying = loadMesh((dir / "column.obj").string());
    ASSERT_TRUE(lying.ok());
    EXPECT_NEAR(extent(*lying).z, 10000.0, 1e-6);
    // 3DS is Z up as 3ds Max writes it: the rock's 3.2 units of height become y.
    if (fs::exists(kModels / "3DS" / "fels.3ds")) {
        auto rock = loadMesh((kModels / "3DS" / "fels.3ds").string());
        ASSERT_TRUE(rock.ok()) << rock.message();
        EXPECT_NEAR(extent(*rock).y, 3.2062, 1e-3);
    }
}

TEST(MeshModel, TexturesAsWindowsExportersNameThem) {
    NEED_TESTMODELS();
    // spider.obj's MTL names ".\SpiderTex.jpg" and the like: found beside it.
    auto spider = loadMesh((kModels / "OBJ" / "spider.obj").string());
    ASSERT_TRUE(spider.ok()) << spider.message();
    EXPECT_FALSE(spider->textures.empty());
    for (const ModelTexture& t : spider->textures) EXPECT_GT(t.width, 1u) << t.name;
    EXPECT_FALSE(warned(*spider, "drawn white"));
    // spider.fbx names the author's disk (D:\projects\...\OBJ\SpiderTex.jpg), not beside it: warned, drawn white.
    auto fbx = loadMesh((kModels / "FBX" / "spider.fbx").string());
    ASSERT_TRUE(fbx.ok());
    EXPECT_TRUE(warned(*fbx, "SpiderTex.jpg")) << (fbx->warnings.empty() ? "" : fbx->warnings[0]);
    // An MTL written on Windows: an absolute path with backslashes, another case.
    const fs::path dir = test::processTempDir("orbis-mesh-mtl");
    fs::copy_file(kModels / "OBJ" / "SpiderTex.jpg", dir / "brick.jpg", fs::copy_options::overwrite_existing);
    std::ofstream(dir / "wall.mtl") << "newmtl Brick\r\nKd 0.8 0.7 0.6\r\nmap_Kd C:\\Users\\bob\\My Textures\\BRICK.JPG\r\n"
                                       "newmtl Lost\r\nKd 1 1 1\r\nmap_Kd textures\\missing.png\r\n";
    std::ofstream(dir / "wall.obj") << "mtllib wall.mtl\r\nv 0 0 0\r\nv 1 0 0\r\nv 1 1 0\r\nv 0 1 0\r\nvt 0 0\r\nvt 1 0\r\nvt 1 1\r\nvt 0 1\r\n"
                                       "usemtl Brick\r\nf 1/1 2/2 3/3\r\nusemtl Lost\r\nf 1/1 3/3 4/4\r\n";
    auto wall = loadMesh((dir / "wall.obj").string());
    ASSERT_TRUE(wall.ok()) << wall.message();
    ASSERT_EQ(wall->textures.size(), 2u);
    const auto material = [&](const std::string& name) -> const ModelMaterial* {
        for (const ModelMaterial& m : wall->materials)
            if (m.name == name) return &m;
        return nullptr;
    };
    ASSERT_TRUE(material("Brick") && material("Lost"));
    EXPECT_GT(wall->textures[size_t(material("Brick")->baseColorTexture)].width, 1u);
    EXPECT_EQ(wall->textures[size_t(material("Lost")->baseColorTexture)].width, 1u);
    EXPECT_TRUE(warned(*wall, "missing.png"));
    EXPECT_FALSE(warned(*wall, "BRICK"));
    EXPECT_NEAR(material("Brick")->baseColorFactor.r, 0.8f, 1e-6f);
}

// Wrap modes as the material says: an MTL's `-clamp on` clamps (the default repeats); one image
// used both ways is two textures.
TEST(MeshModel, TextureWrapModesFollowTheMaterial) {
    const fs::path dir = test::processTempDir("orbis-mesh-wrap");
    ASSERT_TRUE(writePng(dir / "t.png", ImageRgba8{2, 1, {255, 0, 0, 255, 0, 0, 255, 255}}));
    std::ofstream(dir / "q.mtl") << "newmtl R\nmap_Kd t.png\nnewmtl C\nmap_Kd -clamp on t.png\n";
    std::ofstream(dir / "q.obj") << "mtllib q.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0 0\nvt 2 0\nvt 2 1\n"
                                    "usemtl R\nf 1/1 2/2 3/3\nusemtl C\nf 1/1 3/3 2/2\n";
    auto m = loadMesh((dir / "q.obj").string());
    ASSERT_TRUE(m.ok()) << m.message();
    ASSERT_EQ(m->textures.size(), 2u);
    for (const ModelMaterial& mat : m->materials) {
        if (mat.name != "R" && mat.name != "C") continue;
        ASSERT_GE(mat.baseColorTexture, 0) << mat.name;
        const ModelTexture& t = m->textures[size_t(mat.baseColorTexture)];
        const TextureWrap want = mat.name == "C" ? TextureWrap::Clamp : TextureWrap::Repeat;
        EXPECT_EQ(t.wrapU, want) << mat.name;
        EXPECT_EQ(t.wrapV, want) << mat.name;
        EXPECT_EQ(t.width, 2u);
    }
}

// A file's node animations play as glTF's do: a COLLADA node moved by a translation channel
// (keys at 0, 1 and 2 s) is where its keys put it between them; the still node stays.
TEST(MeshModel, NodeAnimationsPlay) {
    const fs::path dir = test::processTempDir("orbis-mesh-anim");
    std::ofstream(dir / "moving.dae") << test::movingNodesCollada(10.0);
    auto m = loadMesh((dir / "moving.dae").string());
    ASSERT_TRUE(m.ok()) << m.message();
    ASSERT_TRUE(m->animated());
    ASSERT_EQ(m->rig.animations.size(), 1u);
    EXPECT_NEAR(m->rig.animations[0].duration, 2.0, 1e-6);
    ASSERT_EQ(m->draws.size(), 2u);
    int still = -1, mover = -1;
    for (const ModelDraw& d : m->draws) {
        ASSERT_GE(d.node, 0);
        (m->rig.nodes[size_t(d.node)].name == "mover" ? mover : still) = d.node;
    }
    ASSERT_GE(mover, 0);
    ASSERT_GE(still, 0);
    PoseEvaluator pose(*m, 0);
    EXPECT_TRUE(pose.moves());
    std::vector<glm::vec4> block(pose.layout().vec4s);
    for (const auto& [t, x, y] : std::vector<std::tuple<double, double, double>>{{0.0, 0, 0}, {0.5, 5, 0}, {1.5, 10, 2.5}, {2.0, 10, 5}}) {
        pose.evaluate(t, block.data());
        const glm::dvec3 at(pose.globals()[size_t(mover)][3]);
        EXPECT_NEAR(at.x, x, 1e-4) << "at " << t << " s";
        EXPECT_NEAR(at.y, y, 1e-4) << "at " << t << " s";
        EXPECT_NEAR(glm::length(glm::dvec3(pose.globals()[size_t(still)][3])), 0.0, 1e-9) << "at " << t << " s";
    }
    // The bounds hold every pose: from the still triangle to the mover's last place.
    EXPECT_NEAR(m->boundsMax.x, 11.0, 1e-3);
    EXPECT_NEAR(m->boundsMax.y, 6.0, 1e-3);
}

TEST(MeshModel, ColladaAndTheModelInsideAKmz) {
    NEED_TESTMODELS();
    const fs::path duck = kModels / "Collada" / "duck.dae";
    auto dae = loadMesh(duck.string());
    ASSERT_TRUE(dae.ok()) << dae.message();
    ASSERT_EQ(dae->textures.size(), 1u);
    EXPECT_GT(dae->textures[0].width, 1u);   // duckCM.tga
    EXPECT_GT(extent(*dae).y, 1.0);
    // The same duck in a KMZ, as SketchUp and Google Earth write them: doc.kml links models/duck.dae.
    const fs::path kmz = test::processTempDir("orbis-mesh-kmz") / "duck.kmz";
    fs::remove(kmz);
    const auto put = [&](const std::string& name, const std::string& bytes) {
        VSILFILE* f = VSIFOpenL(("/vsizip/" + kmz.string() + "/" + name).c_str(), "wb");
        ASSERT_NE(f, nullptr) << name;
        VSIFWriteL(bytes.data(), 1, bytes.size(), f);
        VSIFCloseL(f);
    };
    const auto slurp = [](const fs::path& p) {
        std::ifstream in(p, std::ios::binary);
        return std::string(std::istreambuf_iterator<char>(in), {});
    };
    put("doc.kml", R"(<?xml version="1.0"?><kml xmlns="http://www.opengis.net/kml/2.2"><Placemark><Model>
        <Location><longitude>7</longitude><latitude>46</latitude></Location><Link><href> models/duck.dae </href></Link></Model></Placemark></kml>)");
    put("models/duck.dae", slurp(duck));
    put("models/duckCM.tga", slurp(kModels / "Collada" / "duckCM.tga"));
    auto inside = loadMesh(kmz.string());
    ASSERT_TRUE(inside.ok()) << inside.message();
    EXPECT_EQ(inside->triangles, dae->triangles);
    ASSERT_EQ(inside->textures.size(), 1u);
    EXPECT_EQ(inside->textures[0].width, dae->textures[0].width);
    EXPECT_TRUE(inside->warnings.empty()) << inside->warnings[0];

    // A KMZ whose model path leaves the archive, one with no model, not a zip.
    const fs::path escape = kmz.parent_path() / "escape.kmz";
    fs::remove(escape);
    {
        VSILFILE* f = VSIFOpenL(("/vsizip/" + escape.string() + "/doc.kml").c_str(), "wb");
        const std::string kml = "<kml><Model><Link><href>../../etc/passwd.dae</href></Link></Model></kml>";
        VSIFWriteL(kml.data(), 1, kml.size(), f);
        VSIFCloseL(f);
    }
    auto out = loadMesh(escape.string());
    ASSERT_FALSE(out.ok());
    EXPECT_NE(out.message().find("outside the archive"), std::string::npos) << out.message();
    std::ofstream(kmz.parent_path() / "fake.kmz") << "not a zip";
    auto fake = loadMesh((kmz.parent_path() / "fake.kmz").string());
    ASSERT_FALSE(fake.ok());
    EXPECT_NE(fake.message().find("fake.kmz"), std::string::npos) << fake.message();
}

TEST(MeshModel, HostileFilesGiveClearErrors) {
    const fs::path dir = test::processTempDir("orbis-mesh-hostile");
    struct Case {
        std::string name, bytes, says;
    };
    const std::string tri = R"(<library_geometries><geometry id="tri"><mesh><source id="p"><float_array id="pa" count="9">0 0 0 1 0 0 0 1 0</float_array>
        <technique_common><accessor source="#pa" count="3" stride="3"><param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/></accessor></technique_common></source>
        <vertices id="v"><input semantic="POSITION" source="#p"/></vertices><triangles count="1"><input semantic="VERTEX" source="#v" offset="0"/><p>0 1 2</p></triangles></mesh></geometry></library_geometries>)";
    const auto collada = [&](const std::string& nodes, const std::string& scene) {
        return R"(<?xml version="1.0"?><COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1"><asset><up_axis>Y_UP</up_axis></asset>)" + tri +
               "<library_nodes>" + nodes + R"(</library_nodes><library_visual_scenes><visual_scene id="s">)" + scene +
               R"(</visual_scene></library_visual_scenes><scene><instance_visual_scene url="#s"/></scene></COLLADA>)";
    };
    std::string fan;   // 30 levels, each instancing the next twice: 2^30 nodes
    for (int i = 0; i < 30; ++i)
        fan += "<node id=\"n" + std::to_string(i) + "\"><instance_node url=\"#n" + std::to_string(i + 1) + "\"/><instance_node url=\"#n" +
               std::to_string(i + 1) + "\"/></node>";
    fan += "<node id=\"n30\"><instance_geometry url=\"#tri\"/></node>";
    const std::vector<Case> cases = {
        {"cycle.dae", collada(R"(<node id="a"><instance_geometry url="#tri"/><instance_node url="#b"/></node><node id="b"><node id="c"><instance_node url="#a"/></node></node>)",
                              R"(<node id="root"><instance_node url="#a"/></node>)"),
         "instantiates itself"},
        {"fan.dae", collada(fan, R"(<node id="root"><instance_node url="#n0"/></node>)"), "expands to more than"},
        {"huge.ply", "ply\nformat ascii 1.0\nelement vertex 4000000000\nproperty float x\nproperty float y\nproperty float z\nelement face 1\n"
                     "property list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n",
         "claims 4000000000 vertex elements"},
        {"binary.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 100000\nproperty float x\nproperty float y\nproperty float z\nend_header\n" + std::string(64, '\0'),
         "more than its"},
        {"cut.stl", std::string(80, '\0') + std::string("\x10\x00\x00\x00", 4) + std::string(60, '\0'), "cut.stl"},
        {"garbage.fbx", "Kaydara FBX Binary  \0\x1a\0" + std::string(40, '\xff'), "garbage.fbx"},
        {"points.obj", "v 0 0 0\nv 1 0 0\np 1\np 2\n", "no triangles"},
        {"empty.obj", "", "empty.obj"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.name);
        std::ofstream(dir / c.name, std::ios::binary) << c.bytes;
        auto m = loadMesh((dir / c.name).string());
        ASSERT_FALSE(m.ok());
        EXPECT_NE(m.message().find(c.says), std::string::npos) << m.message();
        EXPECT_NE(m.message().find(c.name), std::string::npos) << m.message();
    }
    // A missing file; a bad option.
    EXPECT_FALSE(loadMesh((dir / "nothing.obj").string()).ok());
    MeshImportOptions bad;
    bad.up = 'x';
    EXPECT_FALSE(loadMesh((dir / "points.obj").string(), bad).ok());
}

TEST(MeshModel, ChecksOnTheirOwn) {
    EXPECT_EQ(checkPlyHeader("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nend_header\n1\n2\n3\n", 60), "");
    EXPECT_NE(checkPlyHeader("ply\nformat ascii 1.0\nelement vertex 3\n", 30).find("end_header"), std::string::npos);
    EXPECT_NE(checkPlyHeader("ply\nelement vertex x\nend_header\n", 30).find("no count"), std::string::npos);
    EXPECT_EQ(checkColladaNodes("<COLLADA><node id='a'/><node id='b'><instance_node url='#a'/><instance_node url='#a'/></node></COLLADA>"), "");
    EXPECT_NE(checkColladaNodes("<COLLADA><node id='a'><instance_node url='#a'/></node></COLLADA>").find("'a' instantiates itself"), std::string::npos);
    EXPECT_EQ(checkColladaNodes("not xml at all <<<"), "");   // left to Assimp
    EXPECT_EQ(kmlModelHref("<kml><Model><Link><href>\n a&amp;b.dae </href></Link></Model></kml>"), "a&b.dae");
    EXPECT_EQ(kmlModelHref("<kml><Placemark><href>x.png</href></Placemark><Model></Model></kml>"), "");
    EXPECT_EQ(kmlModelHref("<kml/>"), "");
    EXPECT_TRUE(isMeshFormat("a/b/C.OBJ"));
    EXPECT_TRUE(isMeshFormat("x.kmz"));
    EXPECT_FALSE(isMeshFormat("x.glb"));
}

}  // namespace
}  // namespace orbis::models
