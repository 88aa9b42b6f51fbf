#include "globe/OgcCapabilities.h"

#include "base/Secrets.h"
#include "globe/CplXml.h"
#include "globe/GdalSetup.h"

#include <cpl_http.h>
#include <cpl_minixml.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <optional>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

namespace orbis::globe {
namespace {

using xml::children;
using xml::corner;
using xml::number;
using xml::text;

nlohmann::ordered_json bounds(double w, double s, double e, double n) {
    if (!(w <= e && s <= n && s >= -90.0 && n <= 90.0)) return nullptr;
    return nlohmann::ordered_json::array({w, s, e, n});
}

/// A WMS Layer and its sublayers, inheriting CRSs and styles as the specification says.
void wmsLayers(const CPLXMLNode* layer, std::vector<std::string> crs, nlohmann::ordered_json& out, int depth) {
    if (depth > 32) return;   // a document nested without end
    for (const char* tag : {"CRS", "SRS"})
        for (const CPLXMLNode* c : children(layer, tag)) {
            std::string v = text(c, "");
            if (!v.empty() && std::find(crs.begin(), crs.end(), v) == crs.end()) crs.push_back(v);
        }
    const std::string name = text(layer, "Name");
    if (!name.empty()) {
        nlohmann::ordered_json l{{"name", name}, {"title", text(layer, "Title")}};
        nlohmann::ordered_json styles = nlohmann::ordered_json::array();
        for (const CPLXMLNode* s : children(layer, "Style")) styles.push_back(text(s, "Name"));
        l["styles"] = styles;
        l["crs"] = crs;
        if (const CPLXMLNode* g = CPLGetXMLNode(const_cast<CPLXMLNode*>(layer), "EX_GeographicBoundingBox")) {
            auto w = number(g, "westBoundLongitude"), e = number(g, "eastBoundLongitude");
            auto s = number(g, "southBoundLatitude"), n = number(g, "northBoundLatitude");
            if (w && e && s && n) l["wgs84Bounds"] = bounds(*w, *s, *e, *n);
        } else if (const CPLXMLNode* b = CPLGetXMLNode(const_cast<CPLXMLNode*>(layer), "LatLonBoundingBox")) {
            auto w = number(b, "minx"), e = number(b, "maxx"), s = number(b, "miny"), n = number(b, "maxy");
            if (w && e && s && n) l["wgs84Bounds"] = bounds(*w, *s, *e, *n);
        }
        for (const char* tag : {"Dimension", "Extent"})
            for (const CPLXMLNode* d : children(layer, tag)) {
                std::string dim = text(d, "name");
                std::transform(dim.begin(), dim.end(), dim.begin(), [](unsigned char ch) { return char(std::tolower(ch)); });
                if (dim == "time" && !text(d, "").empty()) l["time"] = text(d, "");
            }
        out.push_back(l);
    }
    for (const CPLXMLNode* c : children(layer, "Layer")) wmsLayers(c, crs, out, depth + 1);
}

}  // namespace

// Text from the server that is not UTF-8 is written with U+FFFD in its place (never a throw).
Result<std::string> parseOgcCapabilities(std::string_view xml, OgcService service, const std::string& source) {
    const xml::Document root = xml::parse(xml);
    if (!root) return makeError(source + ": the answer is not XML");
    for (const CPLXMLNode* n = root.get(); n; n = n->psNext) {
        if (n->eType != CXT_Element) continue;
        const std::string tag = n->pszValue;
        if (tag == "ServiceExceptionReport" || tag == "ExceptionReport") {
            std::string why = text(n, "ServiceException");
            if (why.empty()) why = text(n, "Exception.ExceptionText");
            return makeError(source + ": the server reports an exception: " + (why.empty() ? std::string("(no text)") : why.substr(0, 500)));
        }
        nlohmann::ordered_json out;
        if (service == OgcService::Wms && (tag == "WMS_Capabilities" || tag == "WMT_MS_Capabilities")) {
            out["service"] = "WMS";
            out["version"] = text(n, "version");
            out["title"] = text(n, "Service.Title");
            nlohmann::ordered_json layers = nlohmann::ordered_json::array();
            if (const CPLXMLNode* cap = CPLGetXMLNode(const_cast<CPLXMLNode*>(n), "Capability"))
                for (const CPLXMLNode* l : children(cap, "Layer")) wmsLayers(l, {}, layers, 0);
            out["layers"] = layers;
            return out.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
        }
        if (service == OgcService::Wmts && tag == "Capabilities") {
            out["service"] = "WMTS";
            out["version"] = text(n, "version");
            out["title"] = text(n, "ServiceIdentification.Title");
            const CPLXMLNode* contents = CPLGetXMLNode(const_cast<CPLXMLNode*>(n), "Contents");
            // Each tile matrix set's CRS, for the layers that link to it.
            std::vector<std::pair<std::string, std::string>> setCrs;
            for (const CPLXMLNode* t : children(contents, "TileMatrixSet"))
                setCrs.emplace_back(text(t, "Identifier"), text(t, "SupportedCRS"));
            nlohmann::ordered_json layers = nlohmann::ordered_json::array();
            for (const CPLXMLNode* f : children(contents, "Layer")) {
                nlohmann::ordered_json l{{"name", text(f, "Identifier")}, {"title", text(f, "Title")}};
                nlohmann::ordered_json styles = nlohmann::ordered_json::array(), formats = nlohmann::ordered_json::array(),
                                       sets = nlohmann::ordered_json::array(), crs = nlohmann::ordered_json::array();
                for (const CPLXMLNode* st : children(f, "Style")) styles.push_back(text(st, "Identifier"));
                for (const CPLXMLNode* fm : children(f, "Format")) formats.push_back(text(fm, ""));
                for (const CPLXMLNode* link : children(f, "TileMatrixSetLink")) {
                    const std::string set = text(link, "TileMatrixSet");
                    sets.push_back(set);
                    for (const auto& [id, c] : setCrs)
                        if (id == set && !c.empty() && std::find(crs.begin(), crs.end(), c) == crs.end()) crs.push_back(c);
                }
                l["styles"] = styles;
                l["crs"] = crs;
                l["formats"] = formats;
                l["tileMatrixSets"] = sets;
                auto lo = corner(f, "WGS84BoundingBox.LowerCorner"), hi = corner(f, "WGS84BoundingBox.UpperCorner");
                if (lo && hi) l["wgs84Bounds"] = bounds(lo->first, lo->second, hi->first, hi->second);
                for (const CPLXMLNode* d : children(f, "Dimension")) {
                    std::string dim = text(d, "Identifier");
                    std::transform(dim.begin(), dim.end(), dim.begin(), [](unsigned char ch) { return char(std::tolower(ch)); });
                    if (dim != "time") continue;
                    std::string values;
                    for (const CPLXMLNode* v : children(d, "Value")) values += (values.empty() ? "" : ",") + text(v, "");
                    if (!values.empty()) l["time"] = values;
                }
                layers.push_back(l);
            }
            out["layers"] = layers;
            return out.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
        }
        if (service == OgcService::Wfs && tag == "WFS_Capabilities") {
            out["service"] = "WFS";
            out["version"] = text(n, "version");
            std::string title = text(n, "ServiceIdentification.Title");
            if (title.empty()) title = text(n, "Service.Title");
            out["title"] = title;
            nlohmann::ordered_json layers = nlohmann::ordered_json::array();
            if (const CPLXMLNode* list = CPLGetXMLNode(const_cast<CPLXMLNode*>(n), "FeatureTypeList"))
                for (const CPLXMLNode* f : children(list, "FeatureType")) {
                    nlohmann::ordered_json l{{"name", text(f, "Name")}, {"title", text(f, "Title")}};
                    std::vector<std::string> crs;
                    for (const char* tag2 : {"DefaultCRS", "DefaultSRS", "SRS", "OtherCRS", "OtherSRS"})
                        for (const CPLXMLNode* c : children(f, tag2))
                            if (!text(c, "").empty()) crs.push_back(text(c, ""));
                    l["crs"] = crs;
                    auto lo = corner(f, "WGS84BoundingBox.LowerCorner"), hi = corner(f, "WGS84BoundingBox.UpperCorner");
                    if (lo && hi) l["wgs84Bounds"] = bounds(lo->first, lo->second, hi->first, hi->second);
                    layers.push_back(l);
                }
            out["layers"] = layers;
            return out.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
        }
    }
    return makeError(source + ": not a " + std::string(service == OgcService::Wms ? "WMS" : service == OgcService::Wmts ? "WMTS" : "WFS") +
                     " capabilities document");
}

Result<std::string> describeOgcServices(const std::string& url) {
    configureGdal();   // HTTP timeouts
    std::string base = url;
    for (const std::string prefix : {"WMS:", "WMTS:", "WFS:"})
        if (base.rfind(prefix, 0) == 0) base = base.substr(prefix.size());
    if (base.rfind("http://", 0) != 0 && base.rfind("https://", 0) != 0)
        return makeError(redactSecrets(url) + ": not an http:// or https:// address");
    std::string upper = base;
    std::transform(upper.begin(), upper.end(), upper.begin(), [](unsigned char c) { return char(std::toupper(c)); });
    const bool onlyWms = upper.find("SERVICE=WMS") != std::string::npos, onlyWfs = upper.find("SERVICE=WFS") != std::string::npos,
               onlyWmts = upper.find("SERVICE=WMTS") != std::string::npos;
    const bool onlyOne = onlyWms || onlyWfs || onlyWmts;
    // A WMTS GetCapabilities address as GDAL takes it: its own REQUEST is left to this code.
    for (const char* own : {"REQUEST=GETCAPABILITIES&", "&REQUEST=GETCAPABILITIES", "REQUEST=GETCAPABILITIES"})
        if (const size_t at = upper.find(own); at != std::string::npos) {
            base.erase(at, std::strlen(own));
            upper.erase(at, std::strlen(own));
        }
    // The address without a SERVICE or REQUEST of its own, ready for parameters.
    if (base.find('?') == std::string::npos) base += '?';
    else if (base.back() != '?' && base.back() != '&') base += '&';
    const std::string shown = redactSecrets(url);
    nlohmann::ordered_json out{{"kind", "ogc-services"}, {"url", shown}};
    bool any = false;
    for (const OgcService service : {OgcService::Wms, OgcService::Wmts, OgcService::Wfs}) {
        const char* name = service == OgcService::Wms ? "WMS" : service == OgcService::Wmts ? "WMTS" : "WFS";
        const bool named = service == OgcService::Wms ? onlyWms : service == OgcService::Wmts ? onlyWmts : onlyWfs;
        if (onlyOne && !named) continue;
        const std::string request = base + (onlyOne ? "" : "SERVICE=" + std::string(name) + "&") + "REQUEST=GetCapabilities";
        CPLPushErrorHandler(CPLQuietErrorHandler);
        CPLHTTPResult* r = CPLHTTPFetch(request.c_str(), nullptr);
        CPLPopErrorHandler();
        std::string error;
        Result<std::string> parsed = makeError("");
        if (!r) error = "no answer";
        else if (r->nStatus != 0 || r->pszErrBuf) error = redactSecrets(r->pszErrBuf ? r->pszErrBuf : "the request failed");
        else parsed = parseOgcCapabilities(std::string_view(reinterpret_cast<const char*>(r->pabyData), size_t(r->nDataLen)), service, shown);
        if (r) CPLHTTPDestroyResult(r);
        const char* key = service == OgcService::Wms ? "wms" : service == OgcService::Wmts ? "wmts" : "wfs";
        if (error.empty() && parsed) {
            out[key] = nlohmann::ordered_json::parse(*parsed);
            any = true;
        } else {
            out[std::string(key) + "Error"] = error.empty() ? parsed.message() : shown + ": " + error;
        }
    }
    if (!any) {
        std::string why;
        for (const char* k : {"wmsError", "wmtsError", "wfsError"})
            if (out.contains(k)) why += (why.empty() ? "" : "; ") + out[k].get<std::string>();
        return makeError(why.empty() ? shown + ": no OGC service answered" : why);
    }
    return out.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
}

}  // namespace orbis::globe
