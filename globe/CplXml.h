#pragma once
// Small helpers over GDAL's XML tree (cpl_minixml) for the OGC documents Orbis reads (service
// capabilities, WPS descriptions and responses): the parsed document owned, the children of an
// element by name, a value's trimmed text, a number, an "x y" corner. Read-only; never throws.

#include "base/Result.h"

#include <cpl_minixml.h>

#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace orbis::globe::xml {

struct Deleter {
    void operator()(CPLXMLNode* n) const { CPLDestroyXMLNode(n); }
};
using Document = std::unique_ptr<CPLXMLNode, Deleter>;

/// Parses `text` quietly (GDAL's messages not printed) and strips every namespace prefix from
/// element and attribute names; nothing when it is not XML.
Document parse(std::string_view text);

/// The children of `node` that are elements called `name`.
std::vector<const CPLXMLNode*> children(const CPLXMLNode* node, const char* name);

/// The value at `path` (CPLGetXMLValue: "A.B", "attribute", "" for the node's own text), trimmed;
/// empty when absent.
std::string text(const CPLXMLNode* node, const char* path);

/// A finite number at `path`; nothing when absent or not a number.
std::optional<double> number(const CPLXMLNode* node, const char* path);

/// `text` with & < > " written as entities, for an element's text or an attribute's value.
std::string escape(std::string_view text);

/// "x y" at `path` (ows:LowerCorner): two finite numbers.
std::optional<std::pair<double, double>> corner(const CPLXMLNode* node, const char* path);

}  // namespace orbis::globe::xml
