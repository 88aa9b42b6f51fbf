#pragma once
// Changes to PostgreSQL tables as they are committed: a thread of its own holds one libpq
// connection that LISTENs on a channel, and hands each NOTIFY's box to the layer (which reads
// again only the feature tiles that the box reaches). A connection that breaks (the server
// restarted, the network dropped) is reported in status() and opened again, 0.5 s after the
// break and up to 5 s apart; once back, a change "anywhere" is reported, since notifications
// sent meanwhile were lost. Made only for a layer whose scene asks for it. No Vulkan.
//
// The payload Orbis's trigger sends (pgNotifyTriggerSql) is the changed rows' box in WGS84:
// "west south east north" (degrees, decimal). An empty or unreadable payload (another
// program's trigger) is a change anywhere.

#include "base/Result.h"
#include "layers/vector/VectorReader.h"

#include <atomic>
#include <chrono>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

namespace orbis::vector {

/// A committed change: where (nothing: anywhere).
struct DatabaseChange {
    std::optional<LonLatBounds> box;
    std::chrono::steady_clock::time_point received;
};

/// "west south east north" in degrees; nothing when the text is not four finite numbers with
/// south <= north within [-90, 90] and west <= east within a turn and a half of 0.
std::optional<LonLatBounds> parseChangeBox(std::string_view payload);

/// libpq's connection string for an OGR source: "PG:dbname=x host=y tables=t" gives
/// "dbname=x host=y" (OGR's own options dropped), "PG:postgresql://..." its URI. An error when
/// the source is not a PostgreSQL connection, or libpq cannot parse it (the message has no
/// password).
Result<std::string> libpqConnection(const std::string& ogrSource);

/// The SQL that makes `table` notify `channel` of its committed changes with their box in
/// WGS84 (Orbis's payload), from its geometry column `geometry` in any SRID: one function
/// (orbis_notify_change, shared by every table) and one statement-level trigger per operation
/// (INSERT, UPDATE, DELETE: one NOTIFY a statement, however many rows; TRUNCATE: anywhere).
/// Run it again: it replaces what it made. `table` may be "schema.table".
std::string pgNotifyTriggerSql(const std::string& table, const std::string& geometry, const std::string& channel);

class PgListener {
public:
    struct Options {
        std::string connection;   ///< libpq's form (libpqConnection)
        std::string channel;
        std::string name;         ///< for messages: the layer
        std::chrono::milliseconds retryMin{500}, retryMax{5000};
        /// SQL run once on the first connection, before LISTEN (the trigger, when the scene
        /// asks Orbis to install it); its failure is reported and listening goes on.
        std::string setupSql;
    };
    /// Starts the thread (it connects in the background). An error for a bad channel name.
    static Result<std::unique_ptr<PgListener>> start(Options options);
    ~PgListener();
    PgListener(const PgListener&) = delete;
    PgListener& operator=(const PgListener&) = delete;

    /// The changes received since the last call, oldest first (at most kKept: past that, one
    /// change anywhere). Any thread.
    std::vector<DatabaseChange> take();
    bool listening() const { return listening_.load(); }
    /// Times the connection was opened again after a break.
    uint64_t reconnects() const { return reconnects_.load(); }
    /// "listening on \"channel\"", or why not ("connection lost: ...; trying again").
    std::string status() const;
    /// Setup SQL's failure, if any.
    std::string setupError() const;

    static constexpr size_t kKept = 1024;

private:
    explicit PgListener(Options options);
    void run();
    void push(DatabaseChange change);
    void setStatus(std::string status);

    Options options_;
    std::atomic<bool> stop_{false}, listening_{false};
    std::atomic<uint64_t> reconnects_{0};
    mutable std::mutex mutex_;
    std::vector<DatabaseChange> pending_;
    std::string status_, setupError_;
    std::thread thread_;
};

}  // namespace orbis::vector
