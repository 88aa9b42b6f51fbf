// orbis-make-vector: synthetic vector data for the vector benchmarks, of any size, written as a
// GeoPackage through OGR (one transaction per 10 000 features).
//
//   orbis-make-vector city --buildings 100000 --out city.gpkg [--centre 9.0,46.0] [--seed 1]
//   orbis-make-vector network --vertices 1000000 --out roads.gpkg [--centre 9.0,46.0] [--seed 1]
//
// city: building footprints (rectangles 8 to 40 m a side, turned by a block's angle, one in ten
// with a courtyard) on a grid of 100 m blocks around the centre, with "height" (m: 3 to 150,
// most low), "levels" and "kind" (house, office, tower). network: a street grid's polylines
// (200 m blocks in a square around the centre, each street 1 km of 20 m steps with a little
// wobble, "class" primary / secondary / residential and "name") until the vertex count is
// reached. Lon/lat, EPSG:4326.
// Deterministic: the same arguments give the same file.
#include "tools/gen/SplitMix.h"

#include <gdal_priv.h>
#include <ogrsf_frmts.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <numbers>
#include <string>

namespace {

using Rng = orbis::gen::SplitMix;

struct Options {
    std::string mode, out;
    long count = 0;
    double lon = 9.0, lat = 46.0;
    uint64_t seed = 1;
};

int usage(const char* why) {
    std::fprintf(stderr, "orbis-make-vector: %s\nusage: orbis-make-vector city --buildings N --out FILE.gpkg [--centre LON,LAT] [--seed S]\n"
                         "       orbis-make-vector network --vertices N --out FILE.gpkg [--centre LON,LAT] [--seed S]\n", why);
    return 2;
}

/// Metres east and north of the centre to lon/lat (a local tangent plane: the areas here are a
/// few kilometres).
struct Local {
    double lon0, lat0, mPerDegLat, mPerDegLon;
    Local(double lon, double lat)
        : lon0(lon), lat0(lat), mPerDegLat(111320.0), mPerDegLon(111320.0 * std::cos(lat * std::numbers::pi / 180.0)) {}
    void add(OGRSimpleCurve& c, double e, double n) const { c.addPoint(lon0 + e / mPerDegLon, lat0 + n / mPerDegLat); }
};

OGRLayer* createLayer(GDALDataset& ds, const char* name, OGRwkbGeometryType type) {
    OGRSpatialReference wgs84;
    wgs84.SetWellKnownGeogCS("WGS84");
    wgs84.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    return ds.CreateLayer(name, &wgs84, type, nullptr);
}

int writeCity(GDALDataset& ds, const Options& o) {
    OGRLayer* layer = createLayer(ds, "buildings", wkbPolygon);
    if (!layer) return usage("cannot create the layer");
    OGRFieldDefn height("height", OFTReal), levels("levels", OFTInteger), kind("kind", OFTString);
    layer->CreateField(&height);
    layer->CreateField(&levels);
    layer->CreateField(&kind);
    Rng rng{o.seed};
    const Local local(o.lon, o.lat);
    const long side = long(std::ceil(std::sqrt(double(o.count) / 4.0)));   // blocks a side, 4 buildings a block
    long written = 0;
    for (long b = 0; written < o.count; ++b) {
        if (written % 10000 == 0) ds.StartTransaction();
        const double bx = (double(b % side) - side / 2.0) * 100.0, by = (double(b / side) - side / 2.0) * 100.0;
        const double angle = (rng.uniform() - 0.5) * 0.6;
        for (int k = 0; k < 4 && written < o.count; ++k, ++written) {
            const double cx = bx + (k % 2 ? 25.0 : -25.0), cy = by + (k / 2 ? 25.0 : -25.0);
            const double w = 8.0 + 32.0 * rng.uniform(), d = 8.0 + 32.0 * rng.uniform();
            const double ca = std::cos(angle), sa = std::sin(angle);
            const auto ring = [&](double hw, double hd) {
                auto r = std::make_unique<OGRLinearRing>();
                for (auto [u, v] : {std::pair{-hw, -hd}, {hw, -hd}, {hw, hd}, {-hw, hd}, {-hw, -hd}})
                    local.add(*r, cx + u * ca - v * sa, cy + u * sa + v * ca);
                return r;
            };
            OGRPolygon polygon;
            polygon.addRingDirectly(ring(w / 2, d / 2).release());
            if (rng.uniform() < 0.1 && w > 20 && d > 20) polygon.addRingDirectly(ring(w / 5, d / 5).release());
            const double u = rng.uniform();
            const double h = 3.0 + 147.0 * u * u * u * u;   // most low, a few towers
            OGRFeature f(layer->GetLayerDefn());
            f.SetField("height", std::round(h * 10.0) / 10.0);
            f.SetField("levels", int(std::max(1.0, std::floor(h / 3.2))));
            f.SetField("kind", h > 60 ? "tower" : h > 15 ? "office" : "house");
            f.SetGeometry(&polygon);
            if (layer->CreateFeature(&f) != OGRERR_NONE) return usage("cannot write a feature");
        }
        if (written % 10000 == 0 || written == o.count) ds.CommitTransaction();
    }
    std::printf("orbis-make-vector: %ld buildings in %ld blocks of 100 m\n", written, (written + 3) / 4);
    return 0;
}

int writeNetwork(GDALDataset& ds, const Options& o) {
    OGRLayer* layer = createLayer(ds, "roads", wkbLineString);
    if (!layer) return usage("cannot create the layer");
    OGRFieldDefn cls("class", OFTString), name("name", OFTString);
    layer->CreateField(&cls);
    layer->CreateField(&name);
    Rng rng{o.seed};
    const Local local(o.lon, o.lat);
    constexpr int kSteps = 50;   // 1 km streets of 20 m steps
    const long streets = (o.count + kSteps) / (kSteps + 1);
    // A square of the grid: `rows` streets of 1 km end to end, `perAxis` of them side by side
    // 200 m apart (rows x 1 km = perAxis x 200 m), in each direction.
    const long rows = std::max(1L, long(std::ceil(std::sqrt(double(streets) / 10.0))));
    const long perAxis = std::max(1L, (streets / 2 + rows - 1) / rows);
    long vertices = 0, written = 0;
    for (long s = 0; vertices < o.count; ++s, ++written) {
        if (written % 10000 == 0) ds.StartTransaction();
        const bool eastward = s % 2 == 0;
        const double offset = (double((s / 2) % perAxis) - perAxis / 2.0) * 200.0,
                     start = (double((s / 2) / perAxis) - rows / 2.0) * 1000.0;
        OGRLineString line;
        const int steps = int(std::min<long>(kSteps, o.count - vertices - 1));
        for (int i = 0; i <= steps; ++i) {
            const double along = start + 20.0 * i, across = offset + 2.0 * (rng.uniform() - 0.5);
            if (eastward) local.add(line, along, across);
            else local.add(line, across, along);
        }
        vertices += steps + 1;
        OGRFeature f(layer->GetLayerDefn());
        const long rank = (s / 2) % perAxis;
        f.SetField("class", rank % 10 == 0 ? "primary" : rank % 5 == 0 ? "secondary" : "residential");
        f.SetField("name", ((eastward ? "East " : "North ") + std::to_string(rank)).c_str());
        f.SetGeometry(&line);
        if (layer->CreateFeature(&f) != OGRERR_NONE) return usage("cannot write a feature");
        if ((written + 1) % 10000 == 0 || vertices >= o.count) ds.CommitTransaction();
        if (steps < 1) break;
    }
    std::printf("orbis-make-vector: %ld streets, %ld vertices\n", written, vertices);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    Options o;
    if (argc < 2) return usage("no mode (city or network)");
    o.mode = argv[1];
    for (int i = 2; i + 1 < argc; i += 2) {
        const std::string key = argv[i], value = argv[i + 1];
        char* end = nullptr;
        if (key == "--buildings" || key == "--vertices") o.count = std::strtol(value.c_str(), &end, 10);
        else if (key == "--out") o.out = value;
        else if (key == "--seed") o.seed = std::strtoull(value.c_str(), &end, 10);
        else if (key == "--centre") {
            if (std::sscanf(value.c_str(), "%lf,%lf", &o.lon, &o.lat) != 2) return usage("--centre is LON,LAT");
        } else return usage(("unknown option " + key).c_str());
    }
    if (o.mode != "city" && o.mode != "network") return usage(("unknown mode " + o.mode).c_str());
    if (o.count < 1 || o.count > 100000000) return usage("give --buildings or --vertices from 1 to 100000000");
    if (o.out.empty()) return usage("give --out FILE.gpkg");
    if (!(std::abs(o.lat) < 80.0 && std::abs(o.lon) <= 180.0)) return usage("--centre must be a lon/lat within 80 degrees of the equator");
    GDALAllRegister();
    GDALDriver* driver = GetGDALDriverManager()->GetDriverByName("GPKG");
    if (!driver) return usage("GDAL has no GPKG driver");
    std::remove(o.out.c_str());
    std::unique_ptr<GDALDataset> ds(driver->Create(o.out.c_str(), 0, 0, 0, GDT_Unknown, nullptr));
    if (!ds) return usage(("cannot create " + o.out).c_str());
    return o.mode == "city" ? writeCity(*ds, o) : writeNetwork(*ds, o);
}
