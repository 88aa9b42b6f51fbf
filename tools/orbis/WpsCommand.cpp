// orbis wps: a WPS 1.0.0 server from the command line (formats/wps/WpsClient.h): what it offers,
// what a process takes, and a run with its outputs saved (references fetched) and its times.
//
//   orbis wps URL                                  the processes
//   orbis wps URL --describe ID                    inputs and outputs
//   orbis wps URL --run ID [--input NAME=VALUE]... [--bbox NAME=W,S,E,N] [--file NAME=PATH]
//                  [--async] [--out DIR] [--repeat N]
#include "formats/wps/WpsClient.h"
#include "formats/wps/WpsJob.h"
#include "tools/orbis/Args.h"
#include "tools/orbis/Commands.h"
#include "tools/orbis/Session.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace orbis::cli {
namespace {

namespace fs = std::filesystem;
using namespace orbis::wps;

const char* kHelp =
    "usage: orbis wps URL [--describe ID | --run ID [options]]\n"
    "A WPS 1.0.0 processing server (tools/serve-wps.sh starts the demo one): without options the\n"
    "processes it offers; --describe what a process takes and gives; --run runs it:\n"
    "  --input NAME=VALUE   a literal input (again for several)\n"
    "  --bbox NAME=W,S,E,N  a bounding-box input in EPSG:4326 (lon, lat)\n"
    "  --file NAME=PATH     complex data sent inline (.geojson, .json, .gml, .kml, .csv, .txt)\n"
    "  --async              a stored job, its status polled until it ends (progress shown)\n"
    "  --out DIR            where outputs are written (default: the current folder)\n"
    "  --repeat N           runs timed for the medians (default 1)\n"
    "  --timeout S          per request (default 30 s)\n"
    "Literal outputs are printed; complex ones are written to DIR/OUTPUT.EXT (fetched when given\n"
    "by reference). Exit codes: 0 ok, 1 bad input or a server problem or a failed job, 2 usage.\n";

const char* kindName(DataKind k) { return k == DataKind::Literal ? "literal" : k == DataKind::Complex ? "complex" : "bounding box"; }

std::string domain(const Parameter& p) {
    std::string s;
    if (p.kind == DataKind::Literal) {
        s = p.literal.dataType.empty() ? "any" : p.literal.dataType;
        if (!p.literal.anyValue) {
            std::string choices;
            for (const auto& v : p.literal.values) choices += (choices.empty() ? "" : " | ") + v;
            for (const auto& r : p.literal.ranges) {
                char b[96];
                std::snprintf(b, sizeof b, "%g .. %g", r.min, r.max);
                choices += (choices.empty() ? "" : " | ") + std::string(b);
            }
            s += " in " + choices;
        }
        if (p.literal.defaultValue) s += ", default " + *p.literal.defaultValue;
    } else if (p.kind == DataKind::Complex) {
        for (const auto& f : p.formats) s += (s.empty() ? "" : " | ") + f.mimeType;
    } else {
        for (const auto& c : p.crss) s += (s.empty() ? "" : " | ") + c;
    }
    return s;
}

std::pair<std::string, std::string> nameValue(const std::string& option, const std::string& text) {
    const size_t eq = text.find('=');
    if (eq == std::string::npos || eq == 0) throw UsageError{option + ": \"" + text + "\" is not NAME=VALUE"};
    return {text.substr(0, eq), text.substr(eq + 1)};
}

double msSince(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
}

std::string stats(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const double median = v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
    char b[96];
    std::snprintf(b, sizeof b, "median %.1f ms (%.1f .. %.1f, %zu runs)", median, v.front(), v.back(), v.size());
    return b;
}

}  // namespace

int wpsCommand(const std::vector<std::string>& argv) {
    const Args args(argv, {"--describe", "--run", "--input", "--bbox", "--file", "--out", "--repeat", "--timeout"}, {"--async", "--help"},
                    {{"-h", "--help"}, {"-o", "--out"}});
    if (args.flag("--help")) {
        std::printf("%s", kHelp);
        return kOk;
    }
    if (args.positional().size() != 1) throw UsageError{"give the server's address (one)"};
    const auto describeId = args.value("--describe"), runId = args.value("--run");
    if (describeId && runId) throw UsageError{"--describe or --run, not both"};
    const double timeout = args.number("--timeout", 1.0, 3600.0).value_or(30.0);
    const int repeat = int(args.integer("--repeat", 1, 1000).value_or(1));
    const WpsClient client(args.positional()[0], timeout);

    if (!describeId && !runId) {
        auto caps = client.capabilities();
        if (!caps) return badInput(caps.message());
        std::printf("%s (WPS %s%s%s): %zu processes\n", caps->title.c_str(), caps->version.c_str(), caps->provider.empty() ? "" : ", ",
                    caps->provider.c_str(), caps->processes.size());
        for (const auto& p : caps->processes) std::printf("  %-16s %s\n", p.identifier.c_str(), p.title.c_str());
        return kOk;
    }
    // The inputs first: a usage error needs no server.
    std::vector<InputValue> inputs;
    for (const std::string& text : args.values("--input")) {
        auto [name, value] = nameValue("--input", text);
        inputs.push_back({.identifier = name, .value = value});
    }
    for (const std::string& text : args.values("--bbox")) {
        auto [name, value] = nameValue("--bbox", text);
        double w = 0, s = 0, e = 0, n = 0;
        char extra = 0;
        if (std::sscanf(value.c_str(), "%lf,%lf,%lf,%lf%c", &w, &s, &e, &n, &extra) != 4 || !std::isfinite(w + s + e + n))
            throw UsageError{"--bbox: \"" + value + "\" is not W,S,E,N"};
        inputs.push_back({.identifier = name, .kind = DataKind::BoundingBox, .bbox = {w, s, e, n}, .crs = "epsg:4326"});
    }
    for (const std::string& text : args.values("--file")) {
        auto [name, path] = nameValue("--file", text);
        std::ifstream in(path, std::ios::binary);
        if (!in) return badInput(path + ": cannot be read");
        std::stringstream data;
        data << in.rdbuf();
        if (data.str().size() > kMaxDocumentBytes) return badInput(path + ": larger than " + std::to_string(kMaxDocumentBytes >> 20) + " MB");
        inputs.push_back({.identifier = name, .kind = DataKind::Complex, .value = data.str(), .format = {.mimeType = mimeTypeFor(path)}});
    }
    const auto t0 = std::chrono::steady_clock::now();
    auto d = client.describe(describeId ? *describeId : *runId);
    if (!d) return badInput(d.message());
    const double describeMs = msSince(t0);
    if (describeId) {
        std::printf("%s: %s%s\n", d->identifier.c_str(), d->title.c_str(), d->storeSupported ? " (runs as a stored job too)" : "");
        if (!d->abstract.empty()) std::printf("  %s\n", d->abstract.c_str());
        std::printf("inputs:\n");
        for (const auto& p : d->inputs)
            std::printf("  %-12s %s%s: %s; %s\n", p.identifier.c_str(), kindName(p.kind), p.minOccurs == 0 ? " (optional)" : "",
                        p.title.c_str(), domain(p).c_str());
        std::printf("outputs:\n");
        for (const auto& p : d->outputs) std::printf("  %-12s %s: %s; %s\n", p.identifier.c_str(), kindName(p.kind), p.title.c_str(), domain(p).c_str());
        return kOk;
    }

    // Complex outputs by reference (fetched here), literals inline.
    std::vector<OutputRequest> outputs;
    for (const auto& o : d->outputs) outputs.push_back({.identifier = o.identifier, .asReference = o.kind == DataKind::Complex});
    const fs::path outDir = args.value("--out").value_or(".");
    const bool async = args.flag("--async");

    std::vector<double> executeMs, fetchMs, totalMs;
    for (int run = 0; run < repeat; ++run) {
        const auto start = std::chrono::steady_clock::now();
        auto r = client.execute(*d, inputs, outputs, async);
        if (!r) return badInput(r.message());
        if (async) {
            int last = -1;
            r = client.wait(*r, [&](const ExecuteResponse& s) {
                if (repeat == 1 && s.percent != last) std::printf("progress    %3d %% %s\n", s.percent, s.message.c_str());
                last = s.percent;
                return true;
            });
            if (!r) return badInput(r.message());
        }
        executeMs.push_back(msSince(start));
        if (r->state == JobState::Failed) return badInput(client.url() + ": \"" + d->identifier + "\" failed: " + r->message);
        const auto fetchStart = std::chrono::steady_clock::now();
        for (const OutputValue& o : r->outputs) {
            if (o.kind == DataKind::Literal) {
                if (run == 0) std::printf("%-11s %s%s%s\n", o.identifier.c_str(), o.value.c_str(), o.uom.empty() ? "" : " ", o.uom.c_str());
                continue;
            }
            if (o.kind == DataKind::BoundingBox) {
                if (run == 0) std::printf("%-11s %g, %g, %g, %g (%s)\n", o.identifier.c_str(), o.bbox[0], o.bbox[1], o.bbox[2], o.bbox[3], o.crs.c_str());
                continue;
            }
            std::string data = o.value;
            if (!o.reference.empty()) {
                auto fetched = client.fetch(o.reference);
                if (!fetched) return badInput(fetched.message());
                data = std::move(*fetched);
            }
            if (run > 0) continue;
            std::error_code ec;
            fs::create_directories(outDir, ec);
            const fs::path file = outDir / (o.identifier + extensionFor(o.format.mimeType));
            std::ofstream out(file, std::ios::binary);
            out << data;
            out.close();
            if (!out) return badInput(file.string() + ": cannot be written");
            std::printf("%-11s %s (%zu bytes, %s)\n", o.identifier.c_str(), file.string().c_str(), data.size(), o.format.mimeType.c_str());
        }
        fetchMs.push_back(msSince(fetchStart));
        totalMs.push_back(msSince(start));
    }
    std::printf("times       describe %.1f ms; execute%s %s; outputs fetched %s; in all %s\n", describeMs, async ? " and poll" : "",
                stats(executeMs).c_str(), stats(fetchMs).c_str(), stats(totalMs).c_str());
    return kOk;
}

}  // namespace orbis::cli
