#pragma once
// A throw-away PostgreSQL (+ PostGIS) server for the tests of database sources: `initdb` into a
// temporary folder, then `postgres` on 127.0.0.1 on a free port, with its socket in that folder
// and no other listener. PostgreSQL refuses to run as root, so when the tests run as root the
// server runs as `nobody` (the folder is handed to it). Every wait is bounded; the destructor
// stops the server (fast shutdown, then SIGKILL) and removes the folder. Statements go through
// `psql` as the cluster's superuser "orbis" (trust authentication, loopback only).
//
//   orbis::test::PostgresServer db;
//   if (!db.available()) GTEST_SKIP() << db.error();
//   ASSERT_TRUE(db.running()) << db.error();
//   ASSERT_EQ(db.sql("CREATE TABLE t (id int, geom geometry(Point, 4326))").exitCode, 0);
//   open(db.ogrConnection());   // "PG:host=127.0.0.1 port=... dbname=orbis user=orbis"

#include "tests/support/Shell.h"

#include <sys/types.h>

#include <chrono>
#include <filesystem>
#include <string>
#include <vector>

namespace orbis::test {

class PostgresServer {
public:
    /// Makes a cluster and starts it, with a database "orbis" (with the PostGIS extension when
    /// `postgis`). With a `password`, connections over TCP must give it (SCRAM-SHA-256); else
    /// they are trusted. Check available() (the packages are there), then running().
    explicit PostgresServer(bool postgis = true, std::string password = {});
    ~PostgresServer();
    PostgresServer(const PostgresServer&) = delete;
    PostgresServer& operator=(const PostgresServer&) = delete;

    /// False when the PostgreSQL or PostGIS packages are missing (error() names them).
    bool available() const { return available_; }
    bool running() const { return pid_ > 0; }
    const std::string& error() const { return error_; }
    int port() const { return port_; }

    /// "host=127.0.0.1 port=N dbname=orbis user=orbis" (libpq's key=value form).
    std::string connection() const;
    /// The same for GDAL's PostgreSQL driver: "PG:" + connection().
    std::string ogrConnection() const { return "PG:" + connection(); }

    /// Runs SQL statements (one or more, separated by ';') through psql in one transaction;
    /// stops at the first error. Output: psql's rows (unaligned, '|' between columns) and errors.
    ShellRun sql(const std::string& statements) const;

    /// Stops the server as an outage would (SIGKILL: no shutdown), for the tests of a server that
    /// goes away. start() brings it back on the same port with the same data.
    void kill();
    /// Starts the server on its port; false (with error()) when it does not answer in time.
    bool start();

private:
    bool makeCluster(bool postgis);
    /// "PGPASSWORD=... " before a client's command line when the server wants a password.
    std::string clientEnv() const;
    /// Runs `argv` (as the server's user when root) to the end, within `limit`; its output goes to
    /// the cluster's log. True on exit status 0.
    bool runTool(const std::vector<std::string>& argv, std::chrono::seconds limit);
    pid_t spawn(const std::vector<std::string>& argv);
    bool waitReady(std::chrono::seconds limit);
    std::string logTail() const;
    void stopServer();

    std::filesystem::path bin_;    // PostgreSQL's programs
    std::filesystem::path root_;   // the temporary folder: data/, the socket, server.log
    bool available_ = false;
    bool dropPrivileges_ = false;  // root: run the server as nobody
    int port_ = 0;
    pid_t pid_ = -1;
    std::string password_;
    std::string error_;
};

}  // namespace orbis::test
