#include "tests/support/PostgresServer.h"

#include "tests/support/Loopback.h"
#include "tests/support/Shell.h"

#include <fcntl.h>
#include <grp.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <thread>
#include <vector>

namespace orbis::test {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

constexpr uid_t kNobody = 65534;
constexpr gid_t kNogroup = 65534;

/// The newest PostgreSQL's programs (Debian: /usr/lib/postgresql/VERSION/bin), or empty.
fs::path postgresBin() {
    fs::path best;
    int bestVersion = -1;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator("/usr/lib/postgresql", ec)) {
        const std::string name = e.path().filename().string();
        const int version = std::atoi(name.c_str());
        if (version > bestVersion && fs::exists(e.path() / "bin" / "postgres") && fs::exists(e.path() / "bin" / "initdb"))
            best = e.path() / "bin", bestVersion = version;
    }
    return best;
}

/// PostGIS's control file for that PostgreSQL (Debian: /usr/share/postgresql/VERSION/extension).
bool postgisInstalled(const fs::path& bin) {
    const std::string version = bin.parent_path().filename().string();
    return fs::exists(fs::path("/usr/share/postgresql") / version / "extension" / "postgis.control");
}

std::string quote(const std::string& s) {   // for a shell command line
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

}  // namespace

PostgresServer::PostgresServer(bool postgis, std::string password) : password_(std::move(password)) {
    bin_ = postgresBin();
    if (bin_.empty()) {
        error_ = "PostgreSQL is not installed (Debian: postgresql-15; tools/install-deps.sh installs it)";
        return;
    }
    if (postgis && !postgisInstalled(bin_)) {
        error_ = "PostGIS is not installed (Debian: postgresql-15-postgis-3; tools/install-deps.sh installs it)";
        return;
    }
    available_ = true;
    dropPrivileges_ = ::geteuid() == 0;
    std::string pattern = (fs::temp_directory_path() / "orbis-pg-XXXXXX").string();
    if (!::mkdtemp(pattern.data())) {
        error_ = "mkdtemp " + pattern + ": " + std::strerror(errno);
        return;
    }
    root_ = pattern;
    if (dropPrivileges_ && ::chown(root_.c_str(), kNobody, kNogroup) != 0) {
        error_ = "chown " + root_.string() + " to nobody: " + std::strerror(errno);
        return;
    }
    ::chmod(root_.c_str(), 0755);
    if (!makeCluster(postgis)) stopServer();
}

PostgresServer::~PostgresServer() {
    stopServer();
    if (!root_.empty()) {
        std::error_code ec;
        fs::remove_all(root_, ec);
    }
}

std::string PostgresServer::connection() const {
    return "host=127.0.0.1 port=" + std::to_string(port_) + " dbname=orbis user=orbis connect_timeout=5";
}

pid_t PostgresServer::spawn(const std::vector<std::string>& argv) {
    const std::string log = (root_ / "server.log").string();
    const pid_t pid = ::fork();
    if (pid != 0) return pid;   // the parent (or -1)
    // The child: its own process group, output to the log, as nobody when root.
    ::setpgid(0, 0);
    const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
    if (fd >= 0) {
        ::dup2(fd, 1);
        ::dup2(fd, 2);
        ::close(fd);
    }
    const int null = ::open("/dev/null", O_RDONLY);
    if (null >= 0) ::dup2(null, 0);
    if (dropPrivileges_ && (::setgroups(0, nullptr) != 0 || ::setgid(kNogroup) != 0 || ::setuid(kNobody) != 0)) ::_exit(126);
    // A test that dies (a crash, a timeout) takes the server with it (set after setuid, which
    // clears it).
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    std::vector<char*> args;
    for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    ::execv(args[0], args.data());
    ::_exit(127);
}

bool PostgresServer::runTool(const std::vector<std::string>& argv, std::chrono::seconds limit) {
    const pid_t pid = spawn(argv);
    if (pid < 0) {
        error_ = std::string("fork: ") + std::strerror(errno);
        return false;
    }
    const int status = waitForChild(pid, limit);
    if (status == 0) return true;
    if (status < 0) {
        ::kill(pid, SIGKILL);
        waitForChild(pid, std::chrono::seconds(5));
    }
    error_ = argv[0] + (status < 0 ? " did not finish within " + std::to_string(limit.count()) + " s"
                                   : " failed (exit " + std::to_string(status) + ")") +
             ": " + logTail();
    return false;
}

bool PostgresServer::makeCluster(bool postgis) {
    // `fsync` off and no sync at initdb: a cluster that lives for one test.
    std::vector<std::string> initdb{(bin_ / "initdb").string(), "-D", (root_ / "data").string(), "-U", "orbis", "-E", "UTF8",
                                    "--no-locale", "--no-sync", "--auth-local=trust"};
    if (password_.empty()) {
        initdb.push_back("--auth-host=trust");
    } else {
        const fs::path pwfile = root_ / "pwfile";
        std::ofstream(pwfile) << password_ << "\n";
        if (dropPrivileges_ && ::chown(pwfile.c_str(), kNobody, kNogroup) != 0) {
            error_ = "chown " + pwfile.string() + " to nobody: " + std::strerror(errno);
            return false;
        }
        initdb.push_back("--auth-host=scram-sha-256");
        initdb.push_back("--pwfile=" + pwfile.string());
    }
    if (!runTool(initdb, std::chrono::seconds(120))) return false;
    // A port from the kernel's ephemeral range; another program could take it before the server
    // does, so a start that fails is tried on a fresh port.
    for (int attempt = 0; attempt < 3; ++attempt) {
        std::string why;
        const int fd = bindLoopback(0, port_, why);
        if (fd < 0) {
            error_ = why;
            return false;
        }
        ::close(fd);
        if (start()) break;
        if (attempt == 2) return false;
    }
    const std::string create = "CREATE DATABASE orbis";
    if (auto r = runShell(clientEnv() + "psql -X -q -v ON_ERROR_STOP=1 -h 127.0.0.1 -p " + std::to_string(port_) +
                          " -U orbis -d postgres -c " + quote(create));
        r.exitCode != 0) {
        error_ = "CREATE DATABASE: " + r.output;
        return false;
    }
    if (postgis) {
        if (auto r = sql("CREATE EXTENSION postgis"); r.exitCode != 0) {
            error_ = "CREATE EXTENSION postgis: " + r.output;
            return false;
        }
    }
    return true;
}

bool PostgresServer::start() {
    if (pid_ > 0) return true;
    // Commits wait for their WAL to reach the OS (fsync stays off): a server killed by kill()
    // keeps every committed row, as a real one would.
    pid_ = spawn({(bin_ / "postgres").string(), "-D", (root_ / "data").string(), "-p", std::to_string(port_), "-k",
                  root_.string(), "-c", "listen_addresses=127.0.0.1", "-c", "fsync=off",
                  "-c", "full_page_writes=off", "-c", "max_connections=40", "-c", "shared_buffers=32MB"});
    if (pid_ < 0) {
        error_ = std::string("fork: ") + std::strerror(errno);
        return false;
    }
    if (waitReady(std::chrono::seconds(30))) return true;
    stopServer();
    return false;
}

bool PostgresServer::waitReady(std::chrono::seconds limit) {
    const auto end = Clock::now() + limit;
    const std::string probe = quote((bin_ / "pg_isready").string()) + " -q -h 127.0.0.1 -p " + std::to_string(port_) +
                              " -U orbis -d postgres -t 1";
    while (Clock::now() < end) {
        if (waitForChild(pid_, std::chrono::milliseconds(0)) >= 0) {   // it exited (port taken, bad data folder)
            pid_ = -1;
            error_ = "postgres exited at start: " + logTail();
            return false;
        }
        if (runShell(probe).exitCode == 0) return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    error_ = "postgres did not answer on 127.0.0.1:" + std::to_string(port_) + " within " + std::to_string(limit.count()) +
             " s: " + logTail();
    return false;
}

ShellRun PostgresServer::sql(const std::string& statements) const {
    if (pid_ <= 0) return {1, "the server is not running"};
    // Through a file: no quoting of the statements on a command line.
    static int serial = 0;
    const fs::path file = root_ / ("statements-" + std::to_string(::getpid()) + "-" + std::to_string(++serial) + ".sql");
    {
        std::ofstream out(file);
        out << statements << ";\n";
    }
    ShellRun r = runShell(clientEnv() + "PGCONNECT_TIMEOUT=5 timeout 120 psql -X -q -A -t -v ON_ERROR_STOP=1 -1 -h 127.0.0.1 -p " +
                          std::to_string(port_) + " -U orbis -d orbis -f " + quote(file.string()));
    std::error_code ec;
    fs::remove(file, ec);
    return r;
}

std::string PostgresServer::clientEnv() const {
    return password_.empty() ? std::string() : "PGPASSWORD=" + quote(password_) + " ";
}

void PostgresServer::kill() {
    if (pid_ <= 0) return;
    ::kill(-pid_, SIGKILL);   // the postmaster and its backends (one process group)
    waitForChild(pid_, std::chrono::seconds(10));
    pid_ = -1;
}

void PostgresServer::stopServer() {
    if (pid_ <= 0) return;
    ::kill(pid_, SIGINT);   // fast shutdown: ends the sessions, no checkpoint wait on clients
    if (waitForChild(pid_, std::chrono::seconds(15)) < 0) {
        ::kill(-pid_, SIGKILL);
        waitForChild(pid_, std::chrono::seconds(5));
    }
    pid_ = -1;
}

std::string PostgresServer::logTail() const {
    std::ifstream in(root_ / "server.log");
    std::stringstream s;
    s << in.rdbuf();
    std::string text = s.str();
    if (text.size() > 1200) text = "..." + text.substr(text.size() - 1200);
    return text.empty() ? "(no output)" : text;
}

}  // namespace orbis::test
