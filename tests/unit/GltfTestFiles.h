#pragma once
// Small synthetic glTF files for tests, with known answers: the binary data goes into one
// base64 data-URI buffer, so a test writes a single .gltf file. Header-only; used by the unit
// tests (GltfAnimationTest) and the render tests (ModelAnimationRenderTest).

#include <nlohmann/json.hpp>

#include <cstdint>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

namespace orbis::test {

inline std::string base64(const std::string& bytes) {
    static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    size_t i = 0;
    for (; i + 2 < bytes.size(); i += 3) {
        const uint32_t v = uint32_t(uint8_t(bytes[i])) << 16 | uint32_t(uint8_t(bytes[i + 1])) << 8 | uint8_t(bytes[i + 2]);
        out += {k[v >> 18], k[(v >> 12) & 63], k[(v >> 6) & 63], k[v & 63]};
    }
    if (i + 1 == bytes.size()) {
        const uint32_t v = uint32_t(uint8_t(bytes[i])) << 16;
        out += {k[v >> 18], k[(v >> 12) & 63], '=', '='};
    } else if (i + 2 == bytes.size()) {
        const uint32_t v = uint32_t(uint8_t(bytes[i])) << 16 | uint32_t(uint8_t(bytes[i + 1])) << 8;
        out += {k[v >> 18], k[(v >> 12) & 63], k[(v >> 6) & 63], '='};
    }
    return out;
}

/// Builds a glTF document: accessors added from arrays, the rest of the JSON set by the test.
class GltfBuilder {
public:
    GltfBuilder() {
        doc["asset"] = {{"version", "2.0"}};
        doc["bufferViews"] = nlohmann::json::array();
        doc["accessors"] = nlohmann::json::array();
    }

    /// Floats, `type` "SCALAR", "VEC3", "VEC4", "MAT4"...; returns the accessor's index.
    int floats(const std::vector<float>& v, const char* type) {
        return add(v.data(), v.size() * 4, 5126, type, v.size() / components(type));
    }
    /// Unsigned shorts (indices: SCALAR; joints: VEC4).
    int ushorts(const std::vector<uint16_t>& v, const char* type) {
        return add(v.data(), v.size() * 2, 5123, type, v.size() / components(type));
    }

    /// The whole file's text.
    std::string text() {
        nlohmann::json d = doc;
        d["buffers"] = {{{"byteLength", bin_.size()}, {"uri", "data:application/octet-stream;base64," + base64(bin_)}}};
        return d.dump(1);
    }

    nlohmann::json doc;

private:
    static size_t components(const std::string& type) {
        return type == "SCALAR" ? 1 : type == "VEC2" ? 2 : type == "VEC3" ? 3 : type == "VEC4" ? 4 : type == "MAT4" ? 16 : 1;
    }
    int add(const void* data, size_t bytes, int componentType, const char* type, size_t count) {
        while (bin_.size() % 4) bin_.push_back('\0');
        doc["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", bin_.size()}, {"byteLength", bytes}});
        bin_.append(static_cast<const char*>(data), bytes);
        doc["accessors"].push_back({{"bufferView", doc["bufferViews"].size() - 1}, {"componentType", componentType},
                                    {"count", count}, {"type", type}});
        return int(doc["accessors"].size() - 1);
    }
    std::string bin_;
};

/// A two-joint arm: joint 0 at the origin, joint 1 one metre up (its child), a skinned mesh on
/// node 2 whose vertices are weighted to either joint or split between them. Joint 1 turns
/// from 0 to 90 degrees about +Z over one second (LINEAR).
inline std::string twoJointArmGltf(const std::vector<int>& skinJoints = {0, 1}) {
    GltfBuilder b;
    // Vertices: 0 at the root (joint 0), 1 at the tip (0, 2, 0) on joint 1, 2 at (1, 0, 0) on
    // joint 0, 3 at the tip again, half on each joint.
    const int pos = b.floats({0, 0, 0, 0, 2, 0, 1, 0, 0, 0, 2, 0}, "VEC3");
    const int normals = b.floats({0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1}, "VEC3");   // given: no flat-normal split of the vertices
    const int joints = b.ushorts({0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0}, "VEC4");
    const int weights = b.floats({1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0.5f, 0.5f, 0, 0}, "VEC4");
    const int idx = b.ushorts({0, 1, 2, 2, 3, 0}, "SCALAR");
    // Inverse bind matrices: joint 0 at the origin (identity), joint 1 at (0, 1, 0).
    std::vector<float> ibm(32, 0.0f);
    for (int i = 0; i < 4; ++i) ibm[size_t(i * 5)] = ibm[size_t(16 + i * 5)] = 1.0f;
    ibm[16 + 13] = -1.0f;   // column 3, row 1
    const int ibmAcc = b.floats(ibm, "MAT4");
    const float s = float(std::sqrt(0.5));
    const int times = b.floats({0, 1}, "SCALAR");
    const int rots = b.floats({0, 0, 0, 1, 0, 0, s, s}, "VEC4");
    nlohmann::json prim = {{"attributes", {{"POSITION", pos}, {"NORMAL", normals}, {"JOINTS_0", joints}, {"WEIGHTS_0", weights}}}, {"indices", idx}};
    b.doc["meshes"] = nlohmann::json::array({{{"primitives", nlohmann::json::array({prim})}}});
    b.doc["nodes"] = nlohmann::json::parse(R"([{"name": "root", "children": [1]}, {"name": "elbow", "translation": [0, 1, 0]},
                                               {"name": "arm", "mesh": 0, "skin": 0, "translation": [100, 0, 0]}])");
    b.doc["skins"] = nlohmann::json::array({{{"joints", skinJoints}, {"inverseBindMatrices", ibmAcc}}});
    nlohmann::json anim = nlohmann::json::parse(R"({"name": "Bend", "channels": [{"sampler": 0, "target": {"node": 1, "path": "rotation"}}]})");
    anim["samplers"] = nlohmann::json::array({{{"input", times}, {"output", rots}, {"interpolation", "LINEAR"}}});
    b.doc["animations"] = nlohmann::json::array({anim});
    b.doc["scenes"] = nlohmann::json::parse(R"([{"nodes": [0, 2]}])");
    b.doc["scene"] = 0;
    return b.text();
}

/// A COLLADA file (Y up, metres) of two triangles (0, 0, 0), (1, 0, 0), (0, 1, 0) scaled by
/// `size`: node "still", and node "mover" whose translation channel has keys at 0, 1 and 2 s
/// putting it at (0, 0, 0), (d, 0, 0) and (d, d / 2, 0), d = `distance`. Read through Assimp.
inline std::string movingNodesCollada(double distance, double size = 1.0) {
    const auto n = [](double v) { return std::to_string(v); };
    return R"(<?xml version="1.0"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1"><asset><up_axis>Y_UP</up_axis></asset>
<library_geometries><geometry id="tri"><mesh><source id="p"><float_array id="pa" count="9">0 0 0 )" + n(size) + " 0 0 0 " + n(size) + R"( 0</float_array>
  <technique_common><accessor source="#pa" count="3" stride="3"><param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/></accessor></technique_common></source>
  <vertices id="v"><input semantic="POSITION" source="#p"/></vertices><triangles count="1"><input semantic="VERTEX" source="#v" offset="0"/><p>0 1 2</p></triangles></mesh></geometry></library_geometries>
<library_animations><animation id="move">
  <source id="in"><float_array id="in-a" count="3">0 1 2</float_array>
    <technique_common><accessor source="#in-a" count="3" stride="1"><param name="TIME" type="float"/></accessor></technique_common></source>
  <source id="out"><float_array id="out-a" count="9">0 0 0 )" + n(distance) + " 0 0 " + n(distance) + " " + n(distance / 2) + R"( 0</float_array>
    <technique_common><accessor source="#out-a" count="3" stride="3"><param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/></accessor></technique_common></source>
  <source id="how"><Name_array id="how-a" count="3">LINEAR LINEAR LINEAR</Name_array>
    <technique_common><accessor source="#how-a" count="3" stride="1"><param name="INTERPOLATION" type="name"/></accessor></technique_common></source>
  <sampler id="s"><input semantic="INPUT" source="#in"/><input semantic="OUTPUT" source="#out"/><input semantic="INTERPOLATION" source="#how"/></sampler>
  <channel source="#s" target="mover/location"/></animation></library_animations>
<library_visual_scenes><visual_scene id="scene">
  <node id="still" name="still"><instance_geometry url="#tri"/></node>
  <node id="mover" name="mover"><translate sid="location">0 0 0</translate><instance_geometry url="#tri"/></node>
</visual_scene></library_visual_scenes><scene><instance_visual_scene url="#scene"/></scene></COLLADA>)";
}

}  // namespace orbis::test
