// orbis-make-mesh: a large test mesh written by Assimp's exporters in the formats the model
// layer reads, for the model loading benchmark (tools/bench-models.sh). The mesh: a rolling
// terrain patch of --side metres, a grid of N x N quads (2 N^2 triangles, N from --triangles),
// with normals, texture coordinates and one coloured material.
//   orbis-make-mesh --triangles 2000000 --out mesh.obj [--side 100]
// Formats by extension: .obj (+ .mtl), .ply (binary), .stl (binary), .dae, .fbx (ASCII: Assimp 5.2 cannot read its own binary FBX 7.5 back), .glb.
#include <assimp/Exporter.hpp>
#include <assimp/material.h>
#include <assimp/scene.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <string>

int main(int argc, char** argv) {
    unsigned long long triangles = 0;
    double side = 100.0;
    std::string out;
    for (int i = 1; i + 1 < argc; i += 2) {
        const std::string a = argv[i];
        if (a == "--triangles") triangles = std::strtoull(argv[i + 1], nullptr, 10);
        else if (a == "--side") side = std::strtod(argv[i + 1], nullptr);
        else if (a == "--out") out = argv[i + 1];
        else return std::fprintf(stderr, "orbis-make-mesh: unknown option %s\n", argv[i]), 2;
    }
    std::string ext = out.substr(out.find_last_of('.') == std::string::npos ? out.size() : out.find_last_of('.'));
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    const std::map<std::string, const char*> formats = {{".obj", "obj"}, {".ply", "plyb"}, {".stl", "stlb"},
                                                        {".dae", "collada"}, {".fbx", "fbxa"}, {".glb", "glb2"}};
    if (triangles < 2 || triangles > 100'000'000ull || out.empty() || !formats.count(ext) || !(side > 0.0)) {
        std::fprintf(stderr, "usage: orbis-make-mesh --triangles N (2..1e8) --out FILE.(obj|ply|stl|dae|fbx|glb) [--side METRES]\n");
        return 2;
    }
    const unsigned n = std::max(1u, unsigned(std::sqrt(double(triangles) / 2.0)));
    // Assimp's FBX exporter declares centimetres (UnitScaleFactor 1): the same patch in them.
    const float unit = ext == ".fbx" ? 100.0f : 1.0f;
    const unsigned verts = (n + 1) * (n + 1);

    aiScene scene;
    scene.mRootNode = new aiNode();
    scene.mRootNode->mName = "terrain";
    scene.mNumMaterials = 1;
    scene.mMaterials = new aiMaterial*[1];
    scene.mMaterials[0] = new aiMaterial();
    aiString name("ground");
    scene.mMaterials[0]->AddProperty(&name, AI_MATKEY_NAME);
    const aiColor4D colour(0.55f, 0.6f, 0.35f, 1.0f);
    scene.mMaterials[0]->AddProperty(&colour, 1, AI_MATKEY_COLOR_DIFFUSE);
    scene.mNumMeshes = 1;
    scene.mMeshes = new aiMesh*[1];
    aiMesh* mesh = scene.mMeshes[0] = new aiMesh();
    mesh->mName = "patch";
    mesh->mMaterialIndex = 0;
    mesh->mPrimitiveTypes = aiPrimitiveType_TRIANGLE;
    mesh->mNumVertices = verts;
    mesh->mVertices = new aiVector3D[verts];
    mesh->mNormals = new aiVector3D[verts];
    mesh->mTextureCoords[0] = new aiVector3D[verts];
    mesh->mNumUVComponents[0] = 2;
    const auto height = [&](double x, double z) { return 3.0 * std::sin(x / 9.0) * std::cos(z / 13.0); };
    for (unsigned j = 0; j <= n; ++j)
        for (unsigned i = 0; i <= n; ++i) {
            const double x = side * (double(i) / n - 0.5), z = side * (double(j) / n - 0.5), e = 1e-3;
            const unsigned k = j * (n + 1) + i;
            mesh->mVertices[k] = aiVector3D(float(x), float(height(x, z)), float(z)) * unit;
            aiVector3D normal(float(-(height(x + e, z) - height(x - e, z)) / (2 * e)), 1.0f, float(-(height(x, z + e) - height(x, z - e)) / (2 * e)));
            normal.Normalize();
            mesh->mNormals[k] = normal;
            mesh->mTextureCoords[0][k] = aiVector3D(float(i) / n, float(j) / n, 0.0f);
        }
    mesh->mNumFaces = 2 * n * n;
    mesh->mFaces = new aiFace[mesh->mNumFaces];
    for (unsigned j = 0, f = 0; j < n; ++j)
        for (unsigned i = 0; i < n; ++i) {
            const unsigned a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
            const unsigned quads[2][3] = {{a, c, b}, {b, c, d}};
            for (const auto& t : quads) {
                aiFace& face = mesh->mFaces[f++];
                face.mNumIndices = 3;
                face.mIndices = new unsigned[3];
                std::memcpy(face.mIndices, t, sizeof t);
            }
        }
    scene.mRootNode->mNumMeshes = 1;
    scene.mRootNode->mMeshes = new unsigned[1]{0};
    Assimp::Exporter exporter;
    if (exporter.Export(&scene, formats.at(ext), out) != AI_SUCCESS) {
        std::fprintf(stderr, "orbis-make-mesh: %s: %s\n", out.c_str(), exporter.GetErrorString());
        return 1;
    }
    std::fprintf(stderr, "orbis-make-mesh: wrote %s: %u triangles, %u vertices\n", out.c_str(), 2 * n * n, verts);
    return 0;
}
