#include "layers/vector/PgListener.h"

#include "base/Secrets.h"

#include <libpq-fe.h>
#include <poll.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <sstream>

namespace orbis::vector {
namespace {

using Clock = std::chrono::steady_clock;

std::string trimmed(std::string_view s) {
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
    return std::string(s);
}

/// libpq's message, one line, without a password.
std::string pqMessage(const PGconn* c) {
    std::string m = trimmed(c ? PQerrorMessage(c) : "out of memory");
    std::replace(m.begin(), m.end(), '\n', ' ');
    return redactSecrets(m);
}

bool validChannel(const std::string& c) {
    if (c.empty() || c.size() > 63 || !(std::isalpha(static_cast<unsigned char>(c[0])) || c[0] == '_')) return false;
    return std::all_of(c.begin(), c.end(), [](char ch) { return std::isalnum(static_cast<unsigned char>(ch)) || ch == '_'; });
}

/// "a"."b" for "a.b": each part quoted as an identifier.
std::string quotedName(const std::string& name) {
    std::string out, part;
    const auto flush = [&] {
        if (!out.empty()) out.push_back('.');
        out.push_back('"');
        for (char ch : part) {
            out.push_back(ch);
            if (ch == '"') out.push_back('"');
        }
        out.push_back('"');
        part.clear();
    };
    for (char ch : name) {
        if (ch == '.') flush();
        else part += ch;
    }
    flush();
    return out;
}

std::string quotedLiteral(const std::string& text) {
    std::string q(1, '\'');
    for (char ch : text) {
        q.push_back(ch);
        if (ch == '\'') q.push_back('\'');
    }
    q.push_back('\'');
    return q;
}

}  // namespace

std::optional<LonLatBounds> parseChangeBox(std::string_view payload) {
    double v[4];
    const char* p = payload.data();
    const char* end = p + payload.size();
    for (double& x : v) {
        while (p < end && (*p == ' ' || *p == '\t')) ++p;
        const auto [next, ec] = std::from_chars(p, end, x);
        if (ec != std::errc() || next == p || !std::isfinite(x)) return std::nullopt;
        p = next;
    }
    while (p < end && (*p == ' ' || *p == '\t' || *p == '\n' || *p == '\r')) ++p;
    if (p != end) return std::nullopt;
    const LonLatBounds b{v[0], v[1], v[2], v[3], false};
    if (!(b.south <= b.north && b.south >= -90.0 && b.north <= 90.0)) return std::nullopt;
    if (!(b.west <= b.east && b.west >= -540.0 && b.east <= 540.0)) return std::nullopt;
    return b;
}

Result<std::string> libpqConnection(const std::string& ogrSource) {
    if (ogrSource.rfind("PG:", 0) != 0 && ogrSource.rfind("pg:", 0) != 0 && ogrSource.rfind("postgresql://", 0) != 0 &&
        ogrSource.rfind("postgres://", 0) != 0)
        return makeError(redactSecrets(ogrSource) + ": not a PostgreSQL connection (\"PG:...\" or \"postgresql://...\")");
    std::string text = ogrSource.rfind("PG:", 0) == 0 || ogrSource.rfind("pg:", 0) == 0 ? ogrSource.substr(3) : ogrSource;
    char* err = nullptr;
    PQconninfoOption* parsed = PQconninfoParse(text.c_str(), &err);
    if (!parsed && text.find("://") == std::string::npos) {
        // OGR's own options (tables=, schemas=, active_schema=, list_all_tables=) are not
        // libpq's: drop them and parse again.
        if (err) PQfreemem(err);
        err = nullptr;
        std::istringstream in(text);
        std::string word, kept;
        while (in >> word) {
            const std::string key = word.substr(0, word.find('='));
            if (key == "tables" || key == "schemas" || key == "active_schema" || key == "list_all_tables") continue;
            kept += (kept.empty() ? "" : " ") + word;
        }
        text = kept;
        parsed = PQconninfoParse(text.c_str(), &err);
    }
    if (!parsed) {
        std::string m = trimmed(err ? err : "cannot parse it");
        if (err) PQfreemem(err);
        return makeError(redactSecrets(ogrSource) + ": not a connection libpq reads: " + redactSecrets(m));
    }
    PQconninfoFree(parsed);
    return text;
}

std::string pgNotifyTriggerSql(const std::string& table, const std::string& geometry, const std::string& channel) {
    const std::string t = quotedName(table);
    // Trigger names are per table; the channel makes them distinct when one table notifies
    // several channels.
    const std::string suffix = "orbis_" + channel;
    std::string sql = R"SQL(CREATE OR REPLACE FUNCTION orbis_notify_change() RETURNS trigger LANGUAGE plpgsql AS $orbis$
DECLARE
    col text := TG_ARGV[0];
    rows text;
    box box2d;
BEGIN
    IF TG_OP = 'TRUNCATE' THEN
        PERFORM pg_notify(TG_ARGV[1], '');
        RETURN NULL;
    END IF;
    rows := CASE TG_OP
        WHEN 'INSERT' THEN format('SELECT %I AS g FROM orbis_new', col)
        WHEN 'DELETE' THEN format('SELECT %I AS g FROM orbis_old', col)
        ELSE format('SELECT %I AS g FROM orbis_old UNION ALL SELECT %I FROM orbis_new', col, col) END;
    EXECUTE format('SELECT ST_Extent(CASE WHEN ST_SRID(g) IN (0, 4326) THEN g ELSE ST_Transform(g, 4326) END) FROM (%s) s', rows)
        INTO box;
    IF box IS NOT NULL THEN
        PERFORM pg_notify(TG_ARGV[1], concat_ws(' ', ST_XMin(box), ST_YMin(box), ST_XMax(box), ST_YMax(box)));
    END IF;
    RETURN NULL;
END
$orbis$;
)SQL";
    std::string args = "(";
    args.append(quotedLiteral(geometry)).append(", ").append(quotedLiteral(channel)).append(")");
    const auto trigger = [&](const std::string& op, const std::string& referencing, const std::string& level) {
        std::string lower = op;
        for (char& ch : lower) ch = char(std::tolower(static_cast<unsigned char>(ch)));
        const std::string name = quotedName(suffix + "_" + lower);
        return "DROP TRIGGER IF EXISTS " + name + " ON " + t + ";\nCREATE TRIGGER " + name + " AFTER " + op + " ON " + t +
               referencing + " FOR EACH " + level + " EXECUTE FUNCTION orbis_notify_change" + args + ";\n";
    };
    sql += trigger("INSERT", " REFERENCING NEW TABLE AS orbis_new", "STATEMENT");
    sql += trigger("UPDATE", " REFERENCING OLD TABLE AS orbis_old NEW TABLE AS orbis_new", "STATEMENT");
    sql += trigger("DELETE", " REFERENCING OLD TABLE AS orbis_old", "STATEMENT");
    sql += trigger("TRUNCATE", "", "STATEMENT");
    return sql;
}

Result<std::unique_ptr<PgListener>> PgListener::start(Options options) {
    if (!validChannel(options.channel))
        return makeError(options.name + ": \"" + options.channel +
                         "\" is not a channel name to LISTEN on (letters, digits and _, at most 63, not starting with a digit)");
    std::unique_ptr<PgListener> l(new PgListener(std::move(options)));
    l->thread_ = std::thread([raw = l.get()] { raw->run(); });
    return l;
}

PgListener::PgListener(Options options) : options_(std::move(options)) { status_ = "connecting"; }

PgListener::~PgListener() {
    stop_ = true;
    if (thread_.joinable()) thread_.join();
}

std::vector<DatabaseChange> PgListener::take() {
    std::lock_guard lock(mutex_);
    return std::exchange(pending_, {});
}

std::string PgListener::status() const {
    std::lock_guard lock(mutex_);
    return status_;
}

std::string PgListener::setupError() const {
    std::lock_guard lock(mutex_);
    return setupError_;
}

void PgListener::push(DatabaseChange change) {
    std::lock_guard lock(mutex_);
    if (pending_.size() >= kKept) {
        pending_.clear();
        change.box.reset();   // too many to tell apart: anywhere
    }
    pending_.push_back(change);
}

void PgListener::setStatus(std::string status) {
    std::lock_guard lock(mutex_);
    status_ = std::move(status);
}

void PgListener::run() {
    bool connectedOnce = false, setupDone = options_.setupSql.empty();
    auto delay = options_.retryMin;
    // Sleeps `d` unless asked to stop meanwhile.
    const auto pause = [this](std::chrono::milliseconds d) {
        const auto until = Clock::now() + d;
        while (!stop_ && Clock::now() < until) std::this_thread::sleep_for(std::chrono::milliseconds(20));
    };
    // Waits for the socket (reading or writing) up to `ms`; false on a poll error.
    const auto waitSocket = [](PGconn* c, bool write, int ms) {
        pollfd fd{PQsocket(c), short(write ? POLLOUT : POLLIN), 0};
        if (fd.fd < 0) return false;
        return ::poll(&fd, 1, ms) >= 0;
    };
    const char* keys[] = {"dbname", "connect_timeout", "application_name", "keepalives_idle", "keepalives_interval", "keepalives_count", nullptr};
    const char* values[] = {options_.connection.c_str(), "5", "orbis-listen", "10", "5", "3", nullptr};
    while (!stop_) {
        // Connect without blocking, so that stopping never waits for a server that does not answer.
        PGconn* c = PQconnectStartParams(keys, values, 1);
        const auto deadline = Clock::now() + std::chrono::seconds(10);
        PostgresPollingStatusType state = PGRES_POLLING_WRITING;
        while (c && PQstatus(c) != CONNECTION_BAD && state != PGRES_POLLING_OK && state != PGRES_POLLING_FAILED && !stop_ &&
               Clock::now() < deadline) {
            if (!waitSocket(c, state == PGRES_POLLING_WRITING, 100)) break;
            state = PQconnectPoll(c);
        }
        if (stop_) {
            PQfinish(c);
            break;
        }
        if (!c || state != PGRES_POLLING_OK || PQstatus(c) != CONNECTION_OK) {
            const std::string why = Clock::now() >= deadline ? "no answer within 10 s" : pqMessage(c);
            PQfinish(c);
            listening_ = false;
            setStatus(std::string(connectedOnce ? "connection lost" : "cannot connect") + ": " + why + "; trying again in " +
                      std::to_string(delay.count()) + " ms");
            pause(delay);
            delay = std::min(delay * 2, options_.retryMax);
            continue;
        }
        // The server's notices ("trigger ... does not exist, skipping") are not the user's business.
        PQsetNoticeProcessor(c, [](void*, const char*) {}, nullptr);
        if (!setupDone) {
            PGresult* r = PQexec(c, options_.setupSql.c_str());
            if (PQresultStatus(r) != PGRES_COMMAND_OK && PQresultStatus(r) != PGRES_TUPLES_OK) {
                std::lock_guard lock(mutex_);
                setupError_ = "installing the change trigger failed: " + pqMessage(c);
            }
            PQclear(r);
            setupDone = true;
        }
        PGresult* r = PQexec(c, ("LISTEN " + quotedName(options_.channel)).c_str());
        const bool ok = PQresultStatus(r) == PGRES_COMMAND_OK;
        PQclear(r);
        if (!ok) {
            setStatus("LISTEN \"" + options_.channel + "\" failed: " + pqMessage(c) + "; trying again");
            PQfinish(c);
            pause(delay);
            delay = std::min(delay * 2, options_.retryMax);
            continue;
        }
        listening_ = true;
        setStatus("listening on \"" + options_.channel + "\"");
        if (connectedOnce) {
            // Notifications sent while the connection was down are lost: anything may have changed.
            ++reconnects_;
            push({std::nullopt, Clock::now()});
        }
        connectedOnce = true;
        delay = options_.retryMin;
        std::string lost;
        while (!stop_) {
            if (!waitSocket(c, false, 100)) {
                lost = "waiting for the server failed";
                break;
            }
            if (!PQconsumeInput(c) || PQstatus(c) != CONNECTION_OK) {
                lost = pqMessage(c);
                break;
            }
            while (PGnotify* n = PQnotifies(c)) {
                push({parseChangeBox(n->extra ? n->extra : ""), Clock::now()});
                PQfreemem(n);
            }
        }
        PQfinish(c);
        listening_ = false;
        if (stop_) break;
        setStatus("connection lost: " + (lost.empty() ? std::string("the server closed it") : lost) + "; trying again");
        pause(delay);
    }
}

}  // namespace orbis::vector
