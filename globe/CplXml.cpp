#include "globe/CplXml.h"

#include <cpl_error.h>

#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace orbis::globe::xml {

Document parse(std::string_view text) {
    const std::string doc(text);
    CPLPushErrorHandler(CPLQuietErrorHandler);
    Document root(CPLParseXMLString(doc.c_str()));
    CPLPopErrorHandler();
    if (root) CPLStripXMLNamespace(root.get(), nullptr, TRUE);
    return root;
}

std::vector<const CPLXMLNode*> children(const CPLXMLNode* node, const char* name) {
    std::vector<const CPLXMLNode*> out;
    for (const CPLXMLNode* c = node ? node->psChild : nullptr; c; c = c->psNext)
        if (c->eType == CXT_Element && std::string_view(c->pszValue) == name) out.push_back(c);
    return out;
}

std::string text(const CPLXMLNode* node, const char* path) {
    const char* v = node ? CPLGetXMLValue(node, path, nullptr) : nullptr;
    std::string s = v ? v : "";
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.pop_back();
    size_t b = 0;
    while (b < s.size() && std::isspace(static_cast<unsigned char>(s[b]))) ++b;
    return s.substr(b);
}

std::optional<double> number(const CPLXMLNode* node, const char* path) {
    const std::string t = text(node, path);
    if (t.empty()) return std::nullopt;
    char* end = nullptr;
    const double v = std::strtod(t.c_str(), &end);
    if (end == t.c_str() || !std::isfinite(v)) return std::nullopt;
    return v;
}

std::string escape(std::string_view text) {
    std::string out;
    out.reserve(text.size());
    for (char c : text) {
        switch (c) {
            case '&': out += "&amp;"; break;
            case '<': out += "&lt;"; break;
            case '>': out += "&gt;"; break;
            case '"': out += "&quot;"; break;
            default: out += c;
        }
    }
    return out;
}

std::optional<std::pair<double, double>> corner(const CPLXMLNode* node, const char* path) {
    const std::string t = text(node, path);
    double a = 0, b = 0;
    char extra = 0;
    if (std::sscanf(t.c_str(), "%lf %lf %c", &a, &b, &extra) != 2 || !std::isfinite(a) || !std::isfinite(b)) return std::nullopt;
    return std::make_pair(a, b);
}

}  // namespace orbis::globe::xml
