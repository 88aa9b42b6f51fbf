#include "formats/wps/WpsDocuments.h"

#include "globe/CplXml.h"

#include <cpl_conv.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <tuple>

namespace orbis::wps {
namespace {

namespace xml = globe::xml;
using xml::escape;

/// The root element (the first element at the top level that is not the XML declaration).
const CPLXMLNode* rootElement(const CPLXMLNode* doc) {
    for (const CPLXMLNode* n = doc; n; n = n->psNext)
        if (n->eType == CXT_Element && n->pszValue && n->pszValue[0] != '?') return n;
    return nullptr;
}

/// An ows:ExceptionReport as an error quoting the server, or nothing.
std::optional<Error> exceptionReport(const CPLXMLNode* root, const std::string& source) {
    if (!root || std::string_view(root->pszValue) != "ExceptionReport") return std::nullopt;
    std::string what;
    for (const CPLXMLNode* e : xml::children(root, "Exception")) {
        if (!what.empty()) what += "; ";
        const std::string code = xml::text(e, "exceptionCode"), locator = xml::text(e, "locator"), text = xml::text(e, "ExceptionText");
        what += code.empty() ? std::string("an exception") : code;
        if (!locator.empty() && locator != "None") what += " (" + locator + ")";
        if (!text.empty()) what += ": " + text;
        if (what.size() > 600) break;
    }
    return makeError(source + ": the server reports " + (what.empty() ? std::string("an exception without text") : what.substr(0, 600)));
}

/// The parsed document and its root element, which must be called `expected`.
Result<std::pair<xml::Document, const CPLXMLNode*>> open(std::string_view text, const char* expected, const char* what,
                                                           const std::string& source) {
    if (text.size() > kMaxDocumentBytes)
        return makeError(source + ": the " + what + " document is larger than " + std::to_string(kMaxDocumentBytes >> 20) + " MB");
    xml::Document doc = xml::parse(text);
    if (!doc) return makeError(source + ": the answer is not XML");
    const CPLXMLNode* root = rootElement(doc.get());
    if (auto e = exceptionReport(root, source)) return *e;
    if (!root || std::string_view(root->pszValue) != expected)
        return makeError(source + ": not a WPS " + what + " document (its root is <" + (root ? root->pszValue : "nothing") + ">, not <" +
                         expected + ">)");
    return std::pair{std::move(doc), root};
}

Format readFormat(const CPLXMLNode* f) { return {xml::text(f, "MimeType"), xml::text(f, "Encoding"), xml::text(f, "Schema")}; }

int occurs(const CPLXMLNode* n, const char* attribute, int fallback) {
    const std::string t = xml::text(n, attribute);
    if (t.empty()) return fallback;
    if (lowerAscii(t) == "unbounded") return 1 << 30;
    char* end = nullptr;
    const long v = std::strtol(t.c_str(), &end, 10);
    if (end == t.c_str() || *end != 0 || v < 0) return fallback;
    return int(std::min<long>(v, 1 << 30));
}

Result<LiteralDomain> readLiteral(const CPLXMLNode* lit, const std::string& where) {
    LiteralDomain d;
    d.dataType = xml::text(lit, "DataType");
    if (d.dataType.empty()) {
        // Only a reference to the XML Schema type ("...#integer"): the part after '#'.
        const std::string ref = xml::text(lit, "DataType.reference");
        d.dataType = ref.substr(ref.find('#') == std::string::npos ? 0 : ref.find('#') + 1);
    }
    d.dataType = lowerAscii(d.dataType);
    if (const size_t colon = d.dataType.find(':'); colon != std::string::npos) d.dataType = d.dataType.substr(colon + 1);   // "xs:int"
    d.uom = xml::text(lit, "UOMs.Default.UOM");
    if (const CPLXMLNode* allowed = CPLGetXMLNode(const_cast<CPLXMLNode*>(lit), "AllowedValues")) {
        d.anyValue = false;
        for (const CPLXMLNode* c = allowed->psChild; c; c = c->psNext) {
            if (c->eType != CXT_Element) continue;
            if (d.values.size() + d.ranges.size() >= kMaxAllowedValues) return makeError(where + ": more than " + std::to_string(kMaxAllowedValues) + " allowed values");
            if (std::string_view(c->pszValue) == "Value") d.values.push_back(xml::text(c, ""));
            else if (std::string_view(c->pszValue) == "Range") {
                ValueRange r;
                const auto lo = xml::number(c, "MinimumValue"), hi = xml::number(c, "MaximumValue");
                r.min = lo.value_or(-INFINITY);
                r.max = hi.value_or(INFINITY);
                if (r.min > r.max) return makeError(where + ": a range from " + std::to_string(r.min) + " to " + std::to_string(r.max));
                r.spacing = xml::number(c, "Spacing");
                const std::string closure = xml::text(c, "rangeClosure");
                if (!closure.empty()) r.closure = closure;
                d.ranges.push_back(r);
            }
        }
    }
    const std::string def = xml::text(lit, "DefaultValue");
    if (CPLGetXMLNode(const_cast<CPLXMLNode*>(lit), "DefaultValue")) d.defaultValue = def;
    return d;
}

/// An Input of DataInputs or an Output of ProcessOutputs.
Result<Parameter> readParameter(const CPLXMLNode* n, bool input, const std::string& where) {
    Parameter p;
    p.identifier = xml::text(n, "Identifier");
    if (p.identifier.empty()) return makeError(where + ": an " + (input ? "input" : "output") + " without an identifier");
    const std::string at = where + " " + (input ? "input" : "output") + " \"" + p.identifier + "\"";
    p.title = xml::text(n, "Title");
    p.abstract = xml::text(n, "Abstract");
    if (input) {
        p.minOccurs = occurs(n, "minOccurs", 1);
        p.maxOccurs = std::max(p.minOccurs, occurs(n, "maxOccurs", 1));
    }
    const CPLXMLNode* lit = CPLGetXMLNode(const_cast<CPLXMLNode*>(n), input ? "LiteralData" : "LiteralOutput");
    const CPLXMLNode* cx = CPLGetXMLNode(const_cast<CPLXMLNode*>(n), input ? "ComplexData" : "ComplexOutput");
    const CPLXMLNode* bb = CPLGetXMLNode(const_cast<CPLXMLNode*>(n), input ? "BoundingBoxData" : "BoundingBoxOutput");
    if (lit) {
        p.kind = DataKind::Literal;
        auto d = readLiteral(lit, at);
        if (!d) return d.error();
        p.literal = std::move(*d);
    } else if (cx) {
        p.kind = DataKind::Complex;
        p.defaultFormat = readFormat(CPLGetXMLNode(const_cast<CPLXMLNode*>(cx), "Default.Format"));
        if (!p.defaultFormat.mimeType.empty()) p.formats.push_back(p.defaultFormat);
        if (const CPLXMLNode* supported = CPLGetXMLNode(const_cast<CPLXMLNode*>(cx), "Supported"))
            for (const CPLXMLNode* f : xml::children(supported, "Format")) {
                Format g = readFormat(f);
                const bool known = std::any_of(p.formats.begin(), p.formats.end(), [&](const Format& h) {
                    return h.mimeType == g.mimeType && h.encoding == g.encoding && h.schema == g.schema;
                });
                if (!g.mimeType.empty() && !known && p.formats.size() < kMaxParameters) p.formats.push_back(std::move(g));
            }
        p.maximumMegabytes = xml::number(cx, "maximumMegabytes").value_or(0.0);
    } else if (bb) {
        p.kind = DataKind::BoundingBox;
        p.defaultCrs = xml::text(bb, "Default.CRS");
        if (const CPLXMLNode* supported = CPLGetXMLNode(const_cast<CPLXMLNode*>(bb), "Supported"))
            for (const CPLXMLNode* c : xml::children(supported, "CRS"))
                if (p.crss.size() < kMaxParameters) p.crss.push_back(xml::text(c, ""));
        if (p.crss.empty() && !p.defaultCrs.empty()) p.crss.push_back(p.defaultCrs);
    } else {
        return makeError(at + ": neither literal, complex nor bounding-box data");
    }
    return p;
}

double parseNumber(const std::string& t, bool& ok) {
    char* end = nullptr;
    const double v = std::strtod(t.c_str(), &end);
    ok = !t.empty() && end != t.c_str() && *end == 0 && std::isfinite(v);
    return v;
}

/// EPSG:4326 (and 4258, and their URNs) put latitude first: OWS corners are in the CRS's axis
/// order, so such a box is written and read "lat lon" (OWSLib, under PyWPS, reads it so).
/// CRS84 is longitude first.
bool latitudeFirst(const std::string& crs) {
    const std::string c = lowerAscii(crs);
    if (c.find("crs84") != std::string::npos) return false;
    for (const char* code : {"4326", "4258", "4269"}) {
        const size_t at = c.rfind(code);
        if (at != std::string::npos && at + 4 == c.size() && (at == 0 || !std::isdigit(static_cast<unsigned char>(c[at - 1])))) return true;
    }
    return false;
}

std::string number(double v) {
    char b[40];
    std::snprintf(b, sizeof b, "%.17g", v);
    return b;
}

}  // namespace

std::string lowerAscii(std::string_view text) {
    std::string s(text);
    for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

bool ValueRange::contains(double v) const {
    const bool openLow = closure == "open" || closure == "open-closed", openHigh = closure == "open" || closure == "closed-open";
    if (openLow ? v <= min : v < min) return false;
    if (openHigh ? v >= max : v > max) return false;
    if (spacing && *spacing > 0.0 && std::isfinite(min)) {
        const double k = (v - min) / *spacing;
        if (std::abs(k - std::round(k)) > 1e-9 * std::max(1.0, std::abs(k))) return false;
    }
    return true;
}

const Parameter* ProcessDescription::input(std::string_view id) const {
    for (const Parameter& p : inputs)
        if (p.identifier == id) return &p;
    return nullptr;
}

const Parameter* ProcessDescription::output(std::string_view id) const {
    for (const Parameter& p : outputs)
        if (p.identifier == id) return &p;
    return nullptr;
}

const char* toString(JobState state) {
    switch (state) {
        case JobState::Accepted: return "accepted";
        case JobState::Started: return "started";
        case JobState::Paused: return "paused";
        case JobState::Succeeded: return "succeeded";
        case JobState::Failed: return "failed";
    }
    return "?";
}

Result<Capabilities> parseCapabilities(std::string_view text, const std::string& source) {
    auto doc = open(text, "Capabilities", "capabilities", source);
    if (!doc) return doc.error();
    const CPLXMLNode* root = doc->second;
    Capabilities c;
    c.version = xml::text(root, "version");
    c.title = xml::text(root, "ServiceIdentification.Title");
    c.abstract = xml::text(root, "ServiceIdentification.Abstract");
    c.provider = xml::text(root, "ServiceProvider.ProviderName");
    if (const CPLXMLNode* ops = CPLGetXMLNode(const_cast<CPLXMLNode*>(root), "OperationsMetadata"))
        for (const CPLXMLNode* op : xml::children(ops, "Operation")) {
            const std::string name = xml::text(op, "name");
            if (name == "DescribeProcess") c.describeGet = xml::text(op, "DCP.HTTP.Get.href");
            if (name == "Execute") {
                c.executeGet = xml::text(op, "DCP.HTTP.Get.href");
                c.executePost = xml::text(op, "DCP.HTTP.Post.href");
            }
        }
    const CPLXMLNode* offerings = CPLGetXMLNode(const_cast<CPLXMLNode*>(root), "ProcessOfferings");
    for (const CPLXMLNode* p : xml::children(offerings, "Process")) {
        if (c.processes.size() >= kMaxProcesses) return makeError(source + ": more than " + std::to_string(kMaxProcesses) + " processes");
        ProcessSummary s{xml::text(p, "Identifier"), xml::text(p, "Title"), xml::text(p, "Abstract"), xml::text(p, "processVersion")};
        if (s.identifier.empty()) return makeError(source + ": a process without an identifier in the capabilities");
        c.processes.push_back(std::move(s));
    }
    return c;
}

Result<std::vector<ProcessDescription>> parseProcessDescriptions(std::string_view text, const std::string& source) {
    auto doc = open(text, "ProcessDescriptions", "process description", source);
    if (!doc) return doc.error();
    std::vector<ProcessDescription> out;
    for (const CPLXMLNode* pd : xml::children(doc->second, "ProcessDescription")) {
        if (out.size() >= kMaxProcesses) return makeError(source + ": more than " + std::to_string(kMaxProcesses) + " processes");
        ProcessDescription d;
        d.identifier = xml::text(pd, "Identifier");
        if (d.identifier.empty()) return makeError(source + ": a process description without an identifier");
        const std::string where = source + ": process \"" + d.identifier + "\"";
        d.title = xml::text(pd, "Title");
        d.abstract = xml::text(pd, "Abstract");
        d.version = xml::text(pd, "processVersion");
        d.storeSupported = lowerAscii(xml::text(pd, "storeSupported")) == "true";
        d.statusSupported = lowerAscii(xml::text(pd, "statusSupported")) == "true";
        for (const auto& [section, item, input] :
             {std::tuple{"DataInputs", "Input", true}, std::tuple{"ProcessOutputs", "Output", false}}) {
            const CPLXMLNode* s = CPLGetXMLNode(const_cast<CPLXMLNode*>(pd), section);
            auto& list = input ? d.inputs : d.outputs;
            for (const CPLXMLNode* n : xml::children(s, item)) {
                if (list.size() >= kMaxParameters)
                    return makeError(where + ": more than " + std::to_string(kMaxParameters) + (input ? " inputs" : " outputs"));
                auto p = readParameter(n, input, where);
                if (!p) return p.error();
                const std::string id = p->identifier;
                if (std::any_of(list.begin(), list.end(), [&](const Parameter& q) { return q.identifier == id; }))
                    return makeError(where + ": two " + (input ? "inputs" : "outputs") + " called \"" + id + "\"");
                list.push_back(std::move(*p));
            }
        }
        out.push_back(std::move(d));
    }
    if (out.empty()) return makeError(source + ": the description lists no process");
    return out;
}

Result<ExecuteResponse> parseExecuteResponse(std::string_view text, const std::string& source) {
    auto doc = open(text, "ExecuteResponse", "execute response", source);
    if (!doc) return doc.error();
    const CPLXMLNode* root = doc->second;
    ExecuteResponse r;
    r.processId = xml::text(root, "Process.Identifier");
    r.statusLocation = xml::text(root, "statusLocation");
    const CPLXMLNode* status = CPLGetXMLNode(const_cast<CPLXMLNode*>(root), "Status");
    if (!status) return makeError(source + ": the execute response has no status");
    r.creationTime = xml::text(status, "creationTime");
    const CPLXMLNode* state = nullptr;
    for (const CPLXMLNode* c = status->psChild; c && !state; c = c->psNext)
        if (c->eType == CXT_Element) state = c;
    const std::string tag = state ? state->pszValue : "";
    auto percent = [&] { return int(std::clamp(xml::number(state, "percentCompleted").value_or(0.0), 0.0, 100.0)); };
    if (tag == "ProcessAccepted") r.state = JobState::Accepted, r.percent = percent(), r.message = xml::text(state, "");
    else if (tag == "ProcessStarted") r.state = JobState::Started, r.percent = percent(), r.message = xml::text(state, "");
    else if (tag == "ProcessPaused") r.state = JobState::Paused, r.percent = percent(), r.message = xml::text(state, "");
    else if (tag == "ProcessSucceeded") r.state = JobState::Succeeded, r.percent = 100, r.message = xml::text(state, "");
    else if (tag == "ProcessFailed") {
        r.state = JobState::Failed;
        const CPLXMLNode* report = CPLGetXMLNode(const_cast<CPLXMLNode*>(state), "ExceptionReport");
        const CPLXMLNode* e = report ? CPLGetXMLNode(const_cast<CPLXMLNode*>(report), "Exception") : nullptr;
        r.message = xml::text(e, "ExceptionText");
        const std::string code = xml::text(e, "exceptionCode");
        if (r.message.empty()) r.message = code.empty() ? std::string("the process failed without a reason") : code;
        r.message = r.message.substr(0, 2000);
    } else {
        return makeError(source + ": the execute response's status is <" + (tag.empty() ? std::string("nothing") : tag) + ">");
    }
    const CPLXMLNode* outputs = CPLGetXMLNode(const_cast<CPLXMLNode*>(root), "ProcessOutputs");
    for (const CPLXMLNode* o : xml::children(outputs, "Output")) {
        if (r.outputs.size() >= kMaxParameters) return makeError(source + ": more than " + std::to_string(kMaxParameters) + " outputs");
        OutputValue v;
        v.identifier = xml::text(o, "Identifier");
        v.title = xml::text(o, "Title");
        if (const CPLXMLNode* ref = CPLGetXMLNode(const_cast<CPLXMLNode*>(o), "Reference")) {
            v.kind = DataKind::Complex;
            v.reference = xml::text(ref, "href");
            v.format = {xml::text(ref, "mimeType"), xml::text(ref, "encoding"), xml::text(ref, "schema")};
            if (v.reference.empty()) return makeError(source + ": output \"" + v.identifier + "\" is a reference without an address");
        } else if (const CPLXMLNode* data = CPLGetXMLNode(const_cast<CPLXMLNode*>(o), "Data")) {
            if (const CPLXMLNode* lit = CPLGetXMLNode(const_cast<CPLXMLNode*>(data), "LiteralData")) {
                v.kind = DataKind::Literal;
                v.value = xml::text(lit, "");
                v.dataType = lowerAscii(xml::text(lit, "dataType"));
                v.uom = xml::text(lit, "uom");
            } else if (const CPLXMLNode* cx = CPLGetXMLNode(const_cast<CPLXMLNode*>(data), "ComplexData")) {
                v.kind = DataKind::Complex;
                v.format = {xml::text(cx, "mimeType"), xml::text(cx, "encoding"), xml::text(cx, "schema")};
                // Text, CDATA, or XML elements inside: serialised back as they came.
                for (const CPLXMLNode* c = cx->psChild; c; c = c->psNext) {
                    if (c->eType == CXT_Attribute) continue;
                    if (c->eType == CXT_Text) v.value += c->pszValue ? c->pszValue : "";
                    else if (c->eType == CXT_Element) {
                        CPLXMLNode copy = *c;
                        copy.psNext = nullptr;
                        char* s = CPLSerializeXMLTree(&copy);
                        if (s) v.value += s;
                        CPLFree(s);
                    }
                    if (v.value.size() > kMaxDocumentBytes) break;
                }
            } else if (const CPLXMLNode* bb = CPLGetXMLNode(const_cast<CPLXMLNode*>(data), "BoundingBoxData")) {
                v.kind = DataKind::BoundingBox;
                v.crs = xml::text(bb, "crs");
                const auto lo = xml::corner(bb, "LowerCorner"), hi = xml::corner(bb, "UpperCorner");
                if (!lo || !hi) return makeError(source + ": output \"" + v.identifier + "\" is a bounding box without two corners");
                v.bbox = latitudeFirst(v.crs) ? std::array<double, 4>{lo->second, lo->first, hi->second, hi->first}
                                              : std::array<double, 4>{lo->first, lo->second, hi->first, hi->second};
            } else {
                return makeError(source + ": output \"" + v.identifier + "\" holds no data the client knows");
            }
        } else {
            return makeError(source + ": output \"" + v.identifier + "\" has neither data nor a reference");
        }
        r.outputs.push_back(std::move(v));
    }
    if (r.state == JobState::Succeeded && r.outputs.empty() && r.statusLocation.empty())
        return makeError(source + ": the process succeeded but the response holds no outputs");
    return r;
}

Result<void> checkInputs(const ProcessDescription& process, std::span<const InputValue> inputs) {
    std::vector<std::string> problems;
    std::map<std::string, int> counts;
    for (const InputValue& in : inputs) {
        const Parameter* p = process.input(in.identifier);
        const std::string name = "input \"" + in.identifier + "\"";
        if (!p) {
            problems.push_back(process.identifier + " has no " + name);
            continue;
        }
        ++counts[in.identifier];
        if (in.kind != p->kind) {
            problems.push_back(name + " is " + (p->kind == DataKind::Literal ? "a literal" : p->kind == DataKind::Complex ? "complex data" : "a bounding box"));
            continue;
        }
        if (p->kind == DataKind::Literal) {
            const LiteralDomain& d = p->literal;
            const std::string& t = d.dataType;
            bool ok = true;
            double v = 0.0;
            const bool numeric = t == "integer" || t == "int" || t == "long" || t == "short" || t == "float" || t == "double" ||
                                 t == "decimal" || t == "nonnegativeinteger" || t == "positiveinteger";
            if (numeric) {
                v = parseNumber(in.value, ok);
                if (!ok) problems.push_back(name + ": \"" + in.value + "\" is not a number");
                else if ((t == "integer" || t == "int" || t == "long" || t == "short" || t == "nonnegativeinteger" || t == "positiveinteger") &&
                         v != std::floor(v)) {
                    problems.push_back(name + ": " + in.value + " is not a whole number");
                    ok = false;
                }
            } else if (t == "boolean") {
                const std::string b = lowerAscii(in.value);
                if (b != "true" && b != "false" && b != "1" && b != "0") problems.push_back(name + ": \"" + in.value + "\" is not true or false"), ok = false;
            }
            if (ok && !d.anyValue) {
                bool allowed = std::find(d.values.begin(), d.values.end(), in.value) != d.values.end();
                if (!allowed && numeric)
                    allowed = std::any_of(d.ranges.begin(), d.ranges.end(), [&](const ValueRange& r) { return r.contains(v); });
                if (!allowed) {
                    std::string choices;
                    for (size_t i = 0; i < d.values.size() && i < 8; ++i) {
                        if (i) choices += ", ";
                        choices += d.values[i];
                    }
                    for (size_t i = 0; i < d.ranges.size() && i < 4; ++i) {
                        if (!choices.empty()) choices += ", ";
                        choices += number(d.ranges[i].min);
                        choices += " .. ";
                        choices += number(d.ranges[i].max);
                    }
                    problems.push_back(name + ": \"" + in.value + "\" is not allowed (" + choices + ")");
                }
            }
        } else if (p->kind == DataKind::Complex) {
            if (in.value.empty() && in.reference.empty()) problems.push_back(name + " has neither data nor a reference");
            if (!in.format.mimeType.empty() && !p->formats.empty() &&
                std::none_of(p->formats.begin(), p->formats.end(), [&](const Format& f) { return lowerAscii(f.mimeType) == lowerAscii(in.format.mimeType); }))
                problems.push_back(name + ": the server takes no " + in.format.mimeType);
        } else {
            const auto& b = in.bbox;
            if (!(std::isfinite(b[0]) && std::isfinite(b[1]) && std::isfinite(b[2]) && std::isfinite(b[3])) || b[0] > b[2] || b[1] > b[3])
                problems.push_back(name + ": the box's lower corner must be below and left of its upper corner");
            if (!in.crs.empty() && !p->crss.empty() && std::find(p->crss.begin(), p->crss.end(), in.crs) == p->crss.end())
                problems.push_back(name + ": the server takes no " + in.crs);
        }
    }
    for (const Parameter& p : process.inputs) {
        const int n = counts.count(p.identifier) ? counts[p.identifier] : 0;
        if (n < p.minOccurs && !(p.kind == DataKind::Literal && p.literal.defaultValue))
            problems.push_back("input \"" + p.identifier + "\" is required" + (p.minOccurs > 1 ? " " + std::to_string(p.minOccurs) + " times" : ""));
        if (n > p.maxOccurs) problems.push_back("input \"" + p.identifier + "\" is given " + std::to_string(n) + " times, at most " + std::to_string(p.maxOccurs));
    }
    if (problems.empty()) return {};
    std::string all = process.identifier + ": ";
    for (size_t i = 0; i < problems.size(); ++i) {
        if (i) all += "; ";
        all += problems[i];
    }
    return makeError(all);
}

std::string executeRequest(const std::string& process, std::span<const InputValue> inputs, std::span<const OutputRequest> outputs, bool async) {
    std::string x =
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
        "<wps:Execute service=\"WPS\" version=\"1.0.0\" xmlns:wps=\"http://www.opengis.net/wps/1.0.0\" "
        "xmlns:ows=\"http://www.opengis.net/ows/1.1\" xmlns:xlink=\"http://www.w3.org/1999/xlink\">\n"
        "  <ows:Identifier>" + escape(process) + "</ows:Identifier>\n  <wps:DataInputs>\n";
    for (const InputValue& in : inputs) {
        x += "    <wps:Input>\n      <ows:Identifier>" + escape(in.identifier) + "</ows:Identifier>\n";
        auto formatAttributes = [&] {
            std::string a;
            if (!in.format.mimeType.empty()) a += " mimeType=\"" + escape(in.format.mimeType) + "\"";
            if (!in.format.encoding.empty()) a += " encoding=\"" + escape(in.format.encoding) + "\"";
            if (!in.format.schema.empty()) a += " schema=\"" + escape(in.format.schema) + "\"";
            return a;
        };
        if (in.kind == DataKind::Complex && !in.reference.empty()) {
            x += "      <wps:Reference xlink:href=\"" + escape(in.reference) + "\"" + formatAttributes() + "/>\n";
        } else {
            x += "      <wps:Data>\n";
            if (in.kind == DataKind::Literal) x += "        <wps:LiteralData>" + escape(in.value) + "</wps:LiteralData>\n";
            else if (in.kind == DataKind::Complex) {
                // XML (a GML or KML document) goes in as elements, anything else as text in CDATA.
                const bool isXml = lowerAscii(in.format.mimeType).find("xml") != std::string::npos ||
                                   lowerAscii(in.format.mimeType).find("gml") != std::string::npos;
                std::string body = in.value;
                if (isXml && body.rfind("<?xml", 0) == 0) body = body.substr(std::min(body.size(), body.find("?>") + 2));
                if (!isXml) {
                    std::string safe;
                    size_t from = 0, at;
                    while ((at = body.find("]]>", from)) != std::string::npos) safe += body.substr(from, at - from) + "]]]]><![CDATA[>", from = at + 3;
                    body = "<![CDATA[" + safe + body.substr(from) + "]]>";
                }
                x += "        <wps:ComplexData" + formatAttributes() + ">" + body + "</wps:ComplexData>\n";
            } else {
                const bool swap = latitudeFirst(in.crs);
                const auto corner = [&](double x, double y) { return swap ? number(y) + " " + number(x) : number(x) + " " + number(y); };
                x += "        <wps:BoundingBoxData" + (in.crs.empty() ? std::string() : " crs=\"" + escape(in.crs) + "\"") +
                     " dimensions=\"2\">\n          <ows:LowerCorner>" + corner(in.bbox[0], in.bbox[1]) +
                     "</ows:LowerCorner>\n          <ows:UpperCorner>" + corner(in.bbox[2], in.bbox[3]) +
                     "</ows:UpperCorner>\n        </wps:BoundingBoxData>\n";
            }
            x += "      </wps:Data>\n";
        }
        x += "    </wps:Input>\n";
    }
    x += "  </wps:DataInputs>\n  <wps:ResponseForm>\n    <wps:ResponseDocument" +
         std::string(async ? " storeExecuteResponse=\"true\" status=\"true\"" : "") + ">\n";
    for (const OutputRequest& o : outputs)
        x += "      <wps:Output" + std::string(o.asReference ? " asReference=\"true\"" : "") +
             (o.mimeType.empty() ? std::string() : " mimeType=\"" + escape(o.mimeType) + "\"") + ">\n        <ows:Identifier>" +
             escape(o.identifier) + "</ows:Identifier>\n      </wps:Output>\n";
    x += "    </wps:ResponseDocument>\n  </wps:ResponseForm>\n</wps:Execute>\n";
    return x;
}

std::string kvpUrl(const std::string& base, std::span<const std::pair<std::string, std::string>> parameters) {
    auto encode = [](const std::string& s) {
        std::string out;
        for (unsigned char c : s) {
            if (std::isalnum(c) || c == '-' || c == '_' || c == '.' || c == '~' || c == ',' || c == ':') out += char(c);
            else {
                char b[4];
                std::snprintf(b, sizeof b, "%%%02X", c);
                out += b;
            }
        }
        return out;
    };
    std::string url = base;
    if (url.find('?') == std::string::npos) url += '?';
    else if (url.back() != '?' && url.back() != '&') url += '&';
    for (size_t i = 0; i < parameters.size(); ++i) {
        if (i) url += '&';
        url += encode(parameters[i].first);
        url += '=';
        url += encode(parameters[i].second);
    }
    return url;
}

}  // namespace orbis::wps
