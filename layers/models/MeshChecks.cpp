// Checks on mesh files before Assimp reads them (MeshChecks.h).
#include "layers/models/MeshChecks.h"

#include <expat.h>

#include <algorithm>
#include <charconv>
#include <cstring>
#include <map>
#include <sstream>
#include <vector>

namespace orbis::models {

std::string checkPlyHeader(std::string_view head, uint64_t fileBytes) {
    const size_t end = head.find("end_header");
    if (head.substr(0, 3) != "ply") return {};   // not PLY: Assimp says so
    if (end == std::string_view::npos) return std::string("its header has no end_header in its first ").append(std::to_string(head.size())).append(" bytes");
    std::istringstream lines{std::string(head.substr(0, end))};
    std::string line;
    bool ascii = true;
    // Per element: its count and the fewest bytes one can take.
    std::vector<std::pair<std::string, std::pair<uint64_t, uint64_t>>> elements;
    const auto typeBytes = [](const std::string& t) -> uint64_t {
        if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
        if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
        if (t == "double" || t == "float64") return 8;
        return 4;
    };
    while (std::getline(lines, line)) {
        std::istringstream words(line);
        std::string word;
        words >> word;
        if (word == "format") {
            std::string f;
            words >> f;
            ascii = f == "ascii";
        } else if (word == "element") {
            std::string name, count;
            words >> name >> count;
            uint64_t n = 0;
            const auto [p, ec] = std::from_chars(count.data(), count.data() + count.size(), n);
            if (ec != std::errc() || p != count.data() + count.size()) return std::string("element '").append(name).append("' has no count it can read (\"").append(count).append("\")");
            elements.push_back({name, {n, 0}});
        } else if (word == "property" && !elements.empty()) {
            std::string type;
            words >> type;
            uint64_t& bytes = elements.back().second.second;
            if (ascii) bytes += 2;   // a digit and a separator at the least
            else bytes += type == "list" ? [&] { std::string countType; words >> countType; return typeBytes(countType); }() : typeBytes(type);
        }
    }
    long double needed = 0;
    for (const auto& [name, e] : elements) {
        needed += (long double)e.first * (long double)std::max<uint64_t>(e.second, 1);
        if (needed > (long double)fileBytes)
            return std::string("its header claims ").append(std::to_string(e.first)).append(" ").append(name).append(" elements, more than its ")
                .append(std::to_string(fileBytes)).append(" bytes can hold");
    }
    return {};
}

namespace {

/// The COLLADA node graph: nodes, nesting and instance_node edges.
struct NodeGraph {
    std::map<std::string, size_t> byId;
    std::vector<std::vector<size_t>> next;   // children and instanced nodes
    std::vector<std::string> names;
    std::vector<size_t> open;                // the nodes being parsed, innermost last
    std::vector<std::pair<size_t, std::string>> instances;   // (node, "#id") resolved at the end
    size_t depth = 0;
    std::vector<size_t> nodeDepth;           // element depth of each open node
    bool tooMany = false;

    size_t node(const std::string& id) {
        if (!id.empty()) {
            auto it = byId.find(id);
            if (it != byId.end()) return it->second;
        }
        const size_t n = next.size();
        next.emplace_back();
        names.push_back(id);
        if (!id.empty()) byId[id] = n;
        return n;
    }
    static const char* attribute(const XML_Char** atts, const char* name) {
        for (int i = 0; atts[i]; i += 2)
            if (std::strcmp(atts[i], name) == 0) return atts[i + 1];
        return nullptr;
    }
    static std::string_view local(const char* name) {
        std::string_view n(name);
        const size_t colon = n.rfind(':');
        return colon == std::string_view::npos ? n : n.substr(colon + 1);
    }
    static void onStart(void* self, const XML_Char* name, const XML_Char** atts) {
        auto& g = *static_cast<NodeGraph*>(self);
        ++g.depth;
        if (g.next.size() > 4 * kMaxColladaNodes) {
            g.tooMany = true;
            return;
        }
        const std::string_view n = local(name);
        if (n == "node") {
            const char* id = attribute(atts, "id");
            const size_t me = g.node(id ? id : "");
            if (!g.open.empty()) g.next[g.open.back()].push_back(me);
            g.open.push_back(me);
            g.nodeDepth.push_back(g.depth);
        } else if (n == "instance_node" && !g.open.empty()) {
            if (const char* url = attribute(atts, "url"); url && url[0] == '#') g.instances.push_back({g.open.back(), url + 1});
        }
    }
    static void onEnd(void* self, const XML_Char*) {
        auto& g = *static_cast<NodeGraph*>(self);
        if (!g.nodeDepth.empty() && g.nodeDepth.back() == g.depth) g.open.pop_back(), g.nodeDepth.pop_back();
        --g.depth;
    }
};

}  // namespace

std::string checkColladaNodes(std::string_view xml) {
    NodeGraph g;
    XML_Parser parser = XML_ParserCreate(nullptr);
    if (!parser) return {};
    XML_SetUserData(parser, &g);
    XML_SetElementHandler(parser, &NodeGraph::onStart, &NodeGraph::onEnd);
    bool parsed = true;
    for (size_t at = 0; at < xml.size() && parsed;) {   // in pieces: an int length each
        const size_t piece = std::min<size_t>(xml.size() - at, size_t(1) << 28);
        parsed = XML_Parse(parser, xml.data() + at, int(piece), at + piece == xml.size()) != XML_STATUS_ERROR;
        at += piece;
    }
    XML_ParserFree(parser);
    if (g.tooMany) return "it has more than " + std::to_string(4 * kMaxColladaNodes) + " nodes";
    if (!parsed) return {};   // Assimp gives its own message
    for (const auto& [from, id] : g.instances) {
        auto it = g.byId.find(id);
        if (it != g.byId.end()) g.next[from].push_back(it->second);
    }
    // Depth-first, iteratively: a node met again while open is a cycle; counts of the expanded
    // tree below each node, saturated.
    const size_t n = g.next.size();
    std::vector<uint8_t> state(n, 0);   // 0 new, 1 open, 2 done
    std::vector<uint64_t> count(n, 1);
    for (size_t root = 0; root < n; ++root) {
        if (state[root]) continue;
        std::vector<std::pair<size_t, size_t>> stack{{root, 0}};
        state[root] = 1;
        while (!stack.empty()) {
            auto& [node, k] = stack.back();
            if (k < g.next[node].size()) {
                const size_t child = g.next[node][k++];
                if (state[child] == 1) {
                    std::string a = g.names[child].empty() ? std::string("a node") : std::string("node '").append(g.names[child]).append("'");
                    return a.append(" instantiates itself (a cycle in its node graph)");
                }
                if (state[child] == 0) state[child] = 1, stack.push_back({child, 0});
                continue;
            }
            for (size_t c : g.next[node]) count[node] = std::min<uint64_t>(count[node] + count[c], kMaxColladaNodes + 1);
            state[node] = 2;
            stack.pop_back();
        }
        if (count[root] > kMaxColladaNodes)
            return "its node graph expands to more than " + std::to_string(kMaxColladaNodes) + " nodes (instanced nodes counted as copies)";
    }
    return {};
}

std::string kmlModelHref(std::string_view kml) {
    const size_t model = kml.find("<Model");
    if (model == std::string_view::npos) return {};
    const size_t modelEnd = kml.find("</Model>", model);
    const size_t open = kml.find("<href>", model);
    if (open == std::string_view::npos || (modelEnd != std::string_view::npos && open > modelEnd)) return {};
    const size_t close = kml.find("</href>", open);
    if (close == std::string_view::npos) return {};
    std::string href(kml.substr(open + 6, close - open - 6));
    const size_t first = href.find_first_not_of(" \t\r\n"), last = href.find_last_not_of(" \t\r\n");
    href = first == std::string::npos ? std::string() : href.substr(first, last - first + 1);
    std::string out;
    out.reserve(href.size());
    for (size_t i = 0; i < href.size(); ++i) {
        out.push_back(href[i]);
        if (href.compare(i, 5, "&amp;") == 0) i += 4;
    }
    return out;
}

}  // namespace orbis::models
