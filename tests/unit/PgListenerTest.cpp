// What needs no server: the NOTIFY payload Orbis's trigger sends, read back (and anything else
// a channel may carry, refused); OGR's PostgreSQL connections turned into libpq's; the trigger's
// SQL quoting the names it is given.
#include "layers/vector/PgListener.h"
#include "layers/vector/VectorOgr.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <thread>

namespace orbis::vector {
namespace {

TEST(PgListener, APayloadIsABoxOfFourNumbersOrAChangeAnywhere) {
    auto b = parseChangeBox("10.5 45.25 11 46");
    ASSERT_TRUE(b);
    EXPECT_DOUBLE_EQ(b->west, 10.5);
    EXPECT_DOUBLE_EQ(b->south, 45.25);
    EXPECT_DOUBLE_EQ(b->east, 11.0);
    EXPECT_DOUBLE_EQ(b->north, 46.0);
    EXPECT_FALSE(b->empty);
    EXPECT_TRUE(parseChangeBox("-180 -90 180 90"));
    EXPECT_TRUE(parseChangeBox("179 10 181 11\n"));   // across the antimeridian, continuous
    EXPECT_TRUE(parseChangeBox("1e1 2 1e1 2"));       // a point: a box of no size
    for (const char* bad : {"", " ", "1 2 3", "1 2 3 4 5", "a b c d", "nan 0 1 1", "inf 0 1 1", "0 10 1 5", "0 -91 1 0",
                            "0 0 1 91", "5 0 4 1", "-600 0 0 1", "0,0,1,1", "1 2 3 4x", "1e400 0 1 1"})
        EXPECT_FALSE(parseChangeBox(bad)) << "\"" << bad << "\"";
}

TEST(PgListener, OgrConnectionsBecomeLibpqsWithoutOgrsOwnOptions) {
    EXPECT_EQ(*libpqConnection("PG:host=127.0.0.1 port=5433 dbname=gis"), "host=127.0.0.1 port=5433 dbname=gis");
    EXPECT_EQ(*libpqConnection("PG:dbname=gis tables=roads,rivers active_schema=osm"), "dbname=gis");
    EXPECT_EQ(*libpqConnection("PG:postgresql://orbis@localhost:5432/gis"), "postgresql://orbis@localhost:5432/gis");
    auto notPg = libpqConnection("/data/roads.gpkg");
    ASSERT_FALSE(notPg);
    EXPECT_NE(notPg.message().find("not a PostgreSQL connection"), std::string::npos) << notPg.message();
    auto bad = libpqConnection("PG:dbname='gis password=hunter2");
    ASSERT_FALSE(bad);
    EXPECT_EQ(bad.message().find("hunter2"), std::string::npos) << bad.message();
}

TEST(PgListener, TheTriggerSqlQuotesTheNamesItIsGiven) {
    const std::string sql = pgNotifyTriggerSql("fleet.vehicles", "the \"geom\"", "cars");
    EXPECT_NE(sql.find("ON \"fleet\".\"vehicles\""), std::string::npos) << sql;
    EXPECT_NE(sql.find("orbis_notify_change('the \"geom\"', 'cars')"), std::string::npos) << sql;
    EXPECT_NE(sql.find("\"orbis_cars_insert\""), std::string::npos) << sql;
    const std::string quote = pgNotifyTriggerSql("t", "g'); DROP TABLE t; --", "c");
    EXPECT_NE(quote.find("'g''); DROP TABLE t; --'"), std::string::npos) << quote;
}

TEST(PgListener, AChannelNameIsAnIdentifier) {
    PgListener::Options o;
    o.name = "vector layer \"Fleet\"";
    o.connection = "host=127.0.0.1 port=1";
    for (const char* bad : {"", "1abc", "a-b", "a b", "x;LISTEN y"}) {
        o.channel = bad;
        auto l = PgListener::start(o);
        ASSERT_FALSE(l) << bad;
        EXPECT_NE(l.message().find("vector layer \"Fleet\""), std::string::npos) << l.message();
    }
}

TEST(PgListener, AServerThatIsNotThereIsReportedAndStoppingDoesNotWait) {
    PgListener::Options o;
    o.connection = "host=127.0.0.1 port=1 dbname=x connect_timeout=5";
    o.channel = "changes";
    o.retryMin = std::chrono::milliseconds(50);
    auto l = PgListener::start(o);
    ASSERT_TRUE(l);
    for (int i = 0; i < 100 && (*l)->status() == "connecting"; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    EXPECT_EQ((*l)->status().rfind("cannot connect: ", 0), 0u) << (*l)->status();
    EXPECT_FALSE((*l)->listening());
    const auto start = std::chrono::steady_clock::now();
    l->reset();
    EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(1));
}

TEST(PgListener, PostgresConnectionsGetTimeoutsUnlessTheyHaveTheirOwn) {
    ::unsetenv("PGCONNECT_TIMEOUT");
    ::unsetenv("PGOPTIONS");
    EXPECT_EQ(detail::withServerTimeouts("PG:dbname=gis"),
              "PG:dbname=gis connect_timeout=10 options='-c statement_timeout=60000'");
    EXPECT_EQ(detail::withServerTimeouts("PG:dbname=gis connect_timeout=3 options='-c work_mem=64MB'"),
              "PG:dbname=gis connect_timeout=3 options='-c work_mem=64MB'");
    EXPECT_EQ(detail::withServerTimeouts("/data/roads.gpkg"), "/data/roads.gpkg");
    EXPECT_EQ(detail::withServerTimeouts("PG:postgresql://localhost/gis"), "PG:postgresql://localhost/gis");
    ::setenv("PGCONNECT_TIMEOUT", "2", 1);
    EXPECT_EQ(detail::withServerTimeouts("PG:dbname=gis"), "PG:dbname=gis options='-c statement_timeout=60000'");
    ::unsetenv("PGCONNECT_TIMEOUT");
}

}  // namespace
}  // namespace orbis::vector
