// PostGIS tables as vector sources, against a real PostgreSQL + PostGIS started on loopback by
// the fixture (tests/support/PostgresServer.h): a table in a projected SRID reads as the same
// features as the same rows in a GeoPackage; a feature tile's read asks the server for its box
// only, through the GiST index; errors name the source and the layer, and a password in the
// connection string never shows in them. Skipped, with the reason, when the packages are missing.
#include "layers/vector/VectorReader.h"
#include "tests/support/PostgresServer.h"

#include <gdal_priv.h>
#include <gtest/gtest.h>
#include <ogrsf_frmts.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace orbis::vector {
namespace {

namespace fs = std::filesystem;

/// A 10 x 10 grid of square parcels in Web Mercator (EPSG:3857) around lon 10, lat 45, each
/// with a name and a height: the same rows go to PostGIS (SQL) and to a GeoPackage (OGR).
struct Parcel {
    int id;
    std::string name;
    double height;
    std::string wkt;
};

std::vector<Parcel> parcels() {
    std::vector<Parcel> out;
    const double x0 = 1113194.9, y0 = 5621521.5, side = 400.0, step = 500.0;
    for (int j = 0; j < 10; ++j)
        for (int i = 0; i < 10; ++i) {
            const double x = x0 + i * step, y = y0 + j * step;
            char wkt[256];
            std::snprintf(wkt, sizeof wkt, "POLYGON((%.3f %.3f,%.3f %.3f,%.3f %.3f,%.3f %.3f,%.3f %.3f))", x, y, x + side, y,
                          x + side, y + side, x, y + side, x, y);
            out.push_back({j * 10 + i + 1, "parcel " + std::to_string(j * 10 + i + 1), 3.5 * (i + j), wkt});
        }
    return out;
}

std::string insertParcels() {
    std::string sql =
        "CREATE TABLE parcels (id integer PRIMARY KEY, name text, height double precision, geom geometry(Polygon, 3857));\n"
        "CREATE INDEX parcels_geom_idx ON parcels USING GIST (geom);\n";
    for (const Parcel& p : parcels())
        sql += "INSERT INTO parcels VALUES (" + std::to_string(p.id) + ", '" + p.name + "', " + std::to_string(p.height) +
               ", ST_GeomFromText('" + p.wkt + "', 3857));\n";
    return sql + "ANALYZE parcels";
}

fs::path writeGeoPackage(const fs::path& path) {
    GDALAllRegister();
    GDALDriver* driver = GetGDALDriverManager()->GetDriverByName("GPKG");
    std::unique_ptr<GDALDataset> ds(driver->Create(path.c_str(), 0, 0, 0, GDT_Unknown, nullptr));
    OGRSpatialReference srs;
    srs.importFromEPSG(3857);
    OGRLayer* layer = ds->CreateLayer("parcels", &srs, wkbPolygon, nullptr);
    OGRFieldDefn id("id", OFTInteger), name("name", OFTString), height("height", OFTReal);
    layer->CreateField(&id);
    layer->CreateField(&name);
    layer->CreateField(&height);
    for (const Parcel& p : parcels()) {
        OGRFeature f(layer->GetLayerDefn());
        f.SetField("id", p.id);
        f.SetField("name", p.name.c_str());
        f.SetField("height", p.height);
        OGRGeometry* g = nullptr;
        OGRGeometryFactory::createFromWkt(p.wkt.c_str(), &srs, &g);
        f.SetGeometryDirectly(g);
        if (layer->CreateFeature(&f) != OGRERR_NONE) ADD_FAILURE() << "GeoPackage: feature " << p.id << " not written";
    }
    return path;
}

struct PostgisSource : ::testing::Test {
    void SetUp() override {
        db = std::make_unique<test::PostgresServer>();
        if (!db->available()) GTEST_SKIP() << db->error();
        ASSERT_TRUE(db->running()) << db->error();
        const auto made = db->sql(insertParcels());
        ASSERT_EQ(made.exitCode, 0) << made.output;
    }
    std::unique_ptr<test::PostgresServer> db;
};

TEST_F(PostgisSource, ATableReadsAsTheSameFeaturesAsAGeoPackage) {
    const fs::path dir = fs::temp_directory_path() / ("orbis-postgis-test-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    VectorReadOptions fromFile, fromServer;
    fromFile.source = writeGeoPackage(dir / "parcels.gpkg").string();
    fromServer.source = db->ogrConnection();
    fromServer.layers = {"parcels"};
    auto file = readVector(fromFile);
    auto server = readVector(fromServer);
    fs::remove_all(dir);
    ASSERT_TRUE(file) << file.message();
    ASSERT_TRUE(server) << server.message();
    ASSERT_EQ(server->layers.size(), 1u);
    const VectorLayer &a = file->layers[0], &b = server->layers[0];
    EXPECT_EQ(b.crs, "EPSG:3857");
    ASSERT_EQ(a.features.size(), 100u);
    ASSERT_EQ(b.features.size(), 100u);
    // Fields in the same order (PostGIS's primary key is the FID, as GeoPackage's is).
    std::vector<std::string> names;
    for (const FieldInfo& f : b.fields) names.push_back(f.name + ":" + f.type);
    EXPECT_EQ(names, (std::vector<std::string>{"name:String", "height:Real"}));
    for (size_t k = 0; k < 100; ++k) {
        const Feature &fa = a.features[k], &fb = b.features[k];
        EXPECT_EQ(fa.fid, fb.fid);
        ASSERT_EQ(fa.coords.size(), fb.coords.size()) << "feature " << k;
        for (size_t v = 0; v < fa.coords.size(); ++v) {
            EXPECT_NEAR(fa.coords[v].x, fb.coords[v].x, 1e-9) << "feature " << k << " vertex " << v;
            EXPECT_NEAR(fa.coords[v].y, fb.coords[v].y, 1e-9) << "feature " << k << " vertex " << v;
        }
        ASSERT_EQ(fb.attributes.size(), 2u);
        EXPECT_EQ(std::get<std::string>(fb.attributes[0]), std::get<std::string>(fa.attributes[1]));
        EXPECT_DOUBLE_EQ(std::get<double>(fb.attributes[1]), std::get<double>(fa.attributes[2]));
    }
    // Around lon 10, lat 45 (Web Mercator's x0, y0 above).
    EXPECT_NEAR(b.bounds.west, 10.0, 1e-3);
    EXPECT_NEAR(b.bounds.south, 45.0, 1e-2);
}

/// The index scans the server has counted on the parcels' GiST index (statistics are flushed
/// when a session ends, so this is read after the reading connection closed).
int64_t indexScans(const test::PostgresServer& db) {
    const auto r = db.sql("SELECT idx_scan FROM pg_stat_user_indexes WHERE indexrelname = 'parcels_geom_idx'");
    return r.exitCode == 0 ? std::atoll(r.output.c_str()) : -1;
}

TEST_F(PostgisSource, ATileReadAsksTheServerForItsBoxThroughTheIndex) {
    // 20 000 more parcels far away (lat 60): enough rows that the planner would rather use the
    // index than read the table, as it would for a real one.
    const auto filled = db->sql(
        "INSERT INTO parcels SELECT 1000 + n, 'far ' || n, 0, "
        "ST_MakeEnvelope(1113194.9 + (n % 200) * 500, 8399737.9 + (n / 200) * 500, 1113594.9 + (n % 200) * 500, "
        "8400137.9 + (n / 200) * 500, 3857) FROM generate_series(0, 19999) AS n; ANALYZE parcels");
    ASSERT_EQ(filled.exitCode, 0) << filled.output;
    const int64_t before = indexScans(*db);
    ASSERT_GE(before, 0);
    VectorReadOptions o;
    o.source = db->ogrConnection();
    o.layers = {"parcels"};
    // The first column's parcels, nothing else: west edge of the grid, lon 10.0 .. 10.004.
    o.within = LonLatBounds{9.99, 44.0, 10.0037, 46.0, false};
    auto data = readVector(o);
    ASSERT_TRUE(data) << data.message();
    std::vector<int64_t> fids;
    for (const Feature& f : data->layers[0].features) fids.push_back(f.fid);
    EXPECT_EQ(fids, (std::vector<int64_t>{1, 11, 21, 31, 41, 51, 61, 71, 81, 91}));
    int64_t after = before;
    for (int wait = 0; wait < 50 && after == before; ++wait) {
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
        after = indexScans(*db);
    }
    EXPECT_GT(after, before) << "the box's query did not use parcels_geom_idx";
}

TEST_F(PostgisSource, BadTablesAndQueriesNameTheSourceAndNeverItsPassword) {
    // Trust authentication ignores the password; what matters is where it could show.
    const std::string source = db->ogrConnection() + " password=hunter2";
    const std::string shown = "PG:host=127.0.0.1 port=" + std::to_string(db->port()) +
                              " dbname=orbis user=orbis connect_timeout=5 password=***";
    VectorReadOptions missing;
    missing.source = source;
    missing.layers = {"no_such_table"};
    auto r = readVector(missing);
    ASSERT_FALSE(r);
    EXPECT_EQ(r.message().rfind(shown + ": no layer 'no_such_table' (layers: ", 0), 0u) << r.message();
    EXPECT_EQ(r.message().find("hunter2"), std::string::npos) << r.message();

    VectorReadOptions badSql;
    badSql.source = source;
    badSql.sql = "SELECT nonsense FROM parcels";
    r = readVector(badSql);
    ASSERT_FALSE(r);
    EXPECT_EQ(r.message().rfind(shown + ": bad SQL statement \"SELECT nonsense FROM parcels\" (", 0), 0u) << r.message();
    EXPECT_EQ(r.message().find("hunter2"), std::string::npos) << r.message();

    // A server that is not there: a clear message within the connect timeout.
    VectorReadOptions gone;
    gone.source = source;
    db->kill();
    const auto start = std::chrono::steady_clock::now();
    r = readVector(gone);
    EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(10));
    ASSERT_FALSE(r);
    EXPECT_EQ(r.message().rfind(shown + ": OGR cannot open it as vector data (", 0), 0u) << r.message();
    EXPECT_EQ(r.message().find("hunter2"), std::string::npos) << r.message();
}

/// Sets an environment variable for a scope, and puts the old value back.
struct ScopedEnv {
    ScopedEnv(const char* name, const std::string& value) : name_(name) {
        if (const char* old = std::getenv(name)) old_ = old;
        ::setenv(name, value.c_str(), 1);
    }
    ~ScopedEnv() {
        if (old_) ::setenv(name_, old_->c_str(), 1);
        else ::unsetenv(name_);
    }
    const char* name_;
    std::optional<std::string> old_;
};

TEST(PostgisPassword, ComesFromTheEnvironmentOrAPgpassFileAndNeverShows) {
    const std::string password = "pw-5ecret";
    test::PostgresServer db(true, password);
    if (!db.available()) GTEST_SKIP() << db.error();
    ASSERT_TRUE(db.running()) << db.error();
    ASSERT_EQ(db.sql("CREATE TABLE spots (id integer PRIMARY KEY, geom geometry(Point, 4326)); "
                     "INSERT INTO spots VALUES (1, ST_SetSRID(ST_MakePoint(7.5, 46.5), 4326))")
                  .exitCode,
              0);
    const fs::path dir = fs::temp_directory_path() / ("orbis-pgpass-test-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    VectorReadOptions o;
    o.source = db.ogrConnection();
    o.layers = {"spots"};
    const auto readsOnePoint = [&] {
        auto r = readVector(o);
        return r && r->layers.size() == 1 && r->layers[0].features.size() == 1;
    };
    {
        // None given: refused, the message names the source and says why.
        ScopedEnv noPassword("PGPASSWORD", ""), noFile("PGPASSFILE", (dir / "none").string());
        auto r = readVector(o);
        ASSERT_FALSE(r);
        EXPECT_EQ(r.message().rfind(db.ogrConnection() + ": OGR cannot open it as vector data (", 0), 0u) << r.message();
        EXPECT_NE(r.message().find("password"), std::string::npos) << r.message();
    }
    {
        ScopedEnv fromEnv("PGPASSWORD", password);
        EXPECT_TRUE(readsOnePoint()) << "with PGPASSWORD";
    }
    {
        const fs::path pgpass = dir / "pgpass";
        std::ofstream(pgpass) << "127.0.0.1:" << db.port() << ":orbis:orbis:" << password << "\n";
        fs::permissions(pgpass, fs::perms::owner_read | fs::perms::owner_write);   // libpq ignores a file others can read
        ScopedEnv noPassword("PGPASSWORD", ""), fromFile("PGPASSFILE", pgpass.string());
        EXPECT_TRUE(readsOnePoint()) << "with a pgpass file";
    }
    {
        // In the connection string it works too, and shows nowhere.
        ScopedEnv noPassword("PGPASSWORD", ""), noFile("PGPASSFILE", (dir / "none").string());
        o.source = db.ogrConnection() + " password=" + password;
        EXPECT_TRUE(readsOnePoint()) << "in the connection string";
        o.layers = {"nothing_here"};
        auto r = readVector(o);
        ASSERT_FALSE(r);
        EXPECT_EQ(r.message().find(password), std::string::npos) << r.message();
    }
    fs::remove_all(dir);
}

}  // namespace
}  // namespace orbis::vector
