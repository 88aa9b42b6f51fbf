// Live PostGIS sources, against a real PostgreSQL + PostGIS on loopback: Orbis's trigger
// announces each committed INSERT, UPDATE and DELETE with its box in WGS84 (from a table in
// Web Mercator), the listener hands them over, a refresh of the pages that box reaches reads the
// new rows, and a server killed and started again is reported, then listened to again, with a
// change "anywhere" for what was missed. Skipped, with the reason, when the packages are missing.
#include "layers/vector/FeatureTiles.h"
#include "layers/vector/PgListener.h"
#include "tests/support/PostgresServer.h"

#include <gtest/gtest.h>

#include <chrono>
#include <memory>
#include <string>
#include <thread>
#include <vector>

namespace orbis::vector {
namespace {

using namespace std::chrono_literals;

/// Vehicles as points in Web Mercator, Orbis's trigger on the table.
struct PostgisLive : ::testing::Test {
    void SetUp() override {
        db = std::make_unique<test::PostgresServer>();
        if (!db->available()) GTEST_SKIP() << db->error();
        ASSERT_TRUE(db->running()) << db->error();
        const auto made = db->sql(
            "CREATE TABLE vehicles (id integer PRIMARY KEY, name text, geom geometry(Point, 3857));\n"
            "CREATE INDEX ON vehicles USING GIST (geom);\n"
            "INSERT INTO vehicles VALUES (1, 'bus', ST_Transform(ST_SetSRID(ST_MakePoint(10, 45), 4326), 3857));\n" +
            pgNotifyTriggerSql("vehicles", "geom", "vehicles_changed"));
        ASSERT_EQ(made.exitCode, 0) << made.output;
    }
    std::unique_ptr<PgListener> listen() {
        PgListener::Options o;
        o.connection = *libpqConnection(db->ogrConnection());
        o.channel = "vehicles_changed";
        o.name = "test";
        auto l = PgListener::start(o);
        EXPECT_TRUE(l) << l.message();
        if (!l) return nullptr;
        for (int i = 0; i < 200 && !(*l)->listening(); ++i) std::this_thread::sleep_for(25ms);
        EXPECT_TRUE((*l)->listening()) << (*l)->status();
        return std::move(*l);
    }
    /// The changes received within `limit`, once at least `count` are in.
    static std::vector<DatabaseChange> waitFor(PgListener& l, size_t count, std::chrono::milliseconds limit = 10s) {
        std::vector<DatabaseChange> got;
        const auto end = std::chrono::steady_clock::now() + limit;
        while (got.size() < count && std::chrono::steady_clock::now() < end) {
            for (auto& c : l.take()) got.push_back(c);
            std::this_thread::sleep_for(10ms);
        }
        return got;
    }
    std::unique_ptr<test::PostgresServer> db;
};

TEST_F(PostgisLive, EachCommittedChangeArrivesWithItsBoxInWgs84) {
    auto l = listen();
    ASSERT_TRUE(l);
    EXPECT_EQ(l->status(), "listening on \"vehicles_changed\"");
    // From a second connection (psql): an insert, a move, a delete, in three transactions.
    ASSERT_EQ(db->sql("INSERT INTO vehicles VALUES (2, 'tram', ST_Transform(ST_SetSRID(ST_MakePoint(11, 46), 4326), 3857))").exitCode, 0);
    ASSERT_EQ(db->sql("UPDATE vehicles SET geom = ST_Transform(ST_SetSRID(ST_MakePoint(10.5, 45.5), 4326), 3857) WHERE id = 1").exitCode, 0);
    ASSERT_EQ(db->sql("DELETE FROM vehicles WHERE id = 2").exitCode, 0);
    const auto got = waitFor(*l, 3);
    ASSERT_EQ(got.size(), 3u);
    for (const auto& c : got) ASSERT_TRUE(c.box);
    EXPECT_NEAR(got[0].box->west, 11.0, 1e-6);
    EXPECT_NEAR(got[0].box->north, 46.0, 1e-6);
    // The move: from where it was to where it is.
    EXPECT_NEAR(got[1].box->west, 10.0, 1e-6);
    EXPECT_NEAR(got[1].box->south, 45.0, 1e-6);
    EXPECT_NEAR(got[1].box->east, 10.5, 1e-6);
    EXPECT_NEAR(got[1].box->north, 45.5, 1e-6);
    EXPECT_NEAR(got[2].box->east, 11.0, 1e-6);
    // A rolled-back change says nothing; an update of many rows is one notification.
    ASSERT_NE(db->sql("BEGIN; DELETE FROM vehicles; SELECT 1/0").exitCode, 0);
    ASSERT_EQ(db->sql("INSERT INTO vehicles SELECT 100 + n, 'car', ST_Transform(ST_SetSRID(ST_MakePoint(n, 0), 4326), 3857) "
                      "FROM generate_series(1, 50) n").exitCode, 0);
    const auto bulk = waitFor(*l, 1);
    ASSERT_EQ(bulk.size(), 1u);
    ASSERT_TRUE(bulk[0].box);
    EXPECT_NEAR(bulk[0].box->west, 1.0, 1e-6);
    EXPECT_NEAR(bulk[0].box->east, 50.0, 1e-6);
    std::this_thread::sleep_for(200ms);
    EXPECT_TRUE(l->take().empty());
}

TEST_F(PostgisLive, ARefreshOfTheNotifiedBoxReadsTheNewRows) {
    auto l = listen();
    ASSERT_TRUE(l);
    FeatureTilesOptions o;
    o.content.read.source = db->ogrConnection();
    o.content.read.layers = {"vehicles"};
    o.pageLevel = 8;
    FeatureTiles pages(o);
    const globe::TileKey here = globe::TileKey::containing(10.0, 45.0, 8);
    auto before = pages.acquire(here);
    ASSERT_TRUE(before) << before.message();
    ASSERT_EQ((*before)->content->layers[0].data.features.size(), 1u);
    ASSERT_EQ(db->sql("INSERT INTO vehicles VALUES (3, 'taxi', ST_Transform(ST_SetSRID(ST_MakePoint(10.01, 45.01), 4326), 3857))").exitCode, 0);
    const auto got = waitFor(*l, 1);
    ASSERT_EQ(got.size(), 1u);
    ASSERT_TRUE(got[0].box);
    const PageRefresh r = pages.refresh(std::span(&*got[0].box, 1));
    EXPECT_EQ(r.pagesRead, 1u);
    EXPECT_EQ(r.changed.size(), 1u);
    auto after = pages.acquire(here);
    ASSERT_TRUE(after);
    EXPECT_EQ((*after)->content->layers[0].data.features.size(), 2u);
}

TEST_F(PostgisLive, AServerThatGoesAwayIsReportedAndListenedToAgainWhenBack) {
    auto l = listen();
    ASSERT_TRUE(l);
    db->kill();
    for (int i = 0; i < 200 && l->listening(); ++i) std::this_thread::sleep_for(25ms);
    EXPECT_FALSE(l->listening());
    EXPECT_EQ(l->status().rfind("connection lost: ", 0), 0u) << l->status();
    // Pages read meanwhile fail, and say so; the server returns on the same port.
    FeatureTilesOptions o;
    o.content.read.source = db->ogrConnection();
    o.content.read.layers = {"vehicles"};
    FeatureTiles pages(o);
    const globe::TileKey here = globe::TileKey::containing(10.0, 45.0, 8);
    EXPECT_FALSE(pages.acquire(here));
    EXPECT_EQ(pages.failingCount(), 1u);
    ASSERT_TRUE(db->start()) << db->error();
    // Listening again, and told that anything may have changed.
    const auto got = waitFor(*l, 1, 20s);
    ASSERT_EQ(got.size(), 1u);
    EXPECT_FALSE(got[0].box);
    EXPECT_TRUE(l->listening());
    EXPECT_EQ(l->reconnects(), 1u);
    const auto updated = db->sql("UPDATE vehicles SET name = 'night bus' WHERE id = 1");
    ASSERT_EQ(updated.exitCode, 0) << updated.output;
    const auto after = waitFor(*l, 1);
    ASSERT_EQ(after.size(), 1u);
    EXPECT_TRUE(after[0].box);
    // The failed page is read again once its retry delay has passed.
    std::this_thread::sleep_for(FeatureTiles::kRetryDelay + 100ms);
    auto page = pages.acquire(here);
    ASSERT_TRUE(page) << page.message();
    EXPECT_EQ(pages.failingCount(), 0u);
}

TEST_F(PostgisLive, TheTriggerCopesWithTruncateNullGeometriesAndUnknownSrids) {
    auto l = listen();
    ASSERT_TRUE(l);
    // A row without a geometry draws nothing: no notification. TRUNCATE: anywhere.
    ASSERT_EQ(db->sql("INSERT INTO vehicles VALUES (7, 'parked', NULL)").exitCode, 0);
    ASSERT_EQ(db->sql("TRUNCATE vehicles").exitCode, 0);
    const auto got = waitFor(*l, 1);
    ASSERT_EQ(got.size(), 1u);
    EXPECT_FALSE(got[0].box);
    // A table without an SRID (0): its coordinates are taken as lon/lat, never an error that
    // would fail the writer's transaction.
    ASSERT_EQ(db->sql("CREATE TABLE raw (id int, g geometry);\n" + pgNotifyTriggerSql("raw", "g", "vehicles_changed") +
                      "INSERT INTO raw VALUES (1, ST_MakePoint(3, 4))").exitCode, 0);
    const auto raw = waitFor(*l, 1);
    ASSERT_EQ(raw.size(), 1u);
    ASSERT_TRUE(raw[0].box);
    EXPECT_NEAR(raw[0].box->west, 3.0, 1e-9);
    EXPECT_NEAR(raw[0].box->south, 4.0, 1e-9);
}

}  // namespace
}  // namespace orbis::vector
