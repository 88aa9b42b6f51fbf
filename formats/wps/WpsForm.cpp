#include "formats/wps/WpsForm.h"

#include "formats/wps/WpsJob.h"

#include "base/FileText.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>

namespace orbis::wps {
namespace {

bool isGeometryFormat(const std::string& mime) {
    const std::string m = lowerAscii(mime);
    return m.find("json") != std::string::npos;
}

std::string rangeHint(const std::vector<ValueRange>& ranges) {
    std::string hint;
    for (const ValueRange& r : ranges) {
        char text[96];
        std::snprintf(text, sizeof text, "%s%g .. %g", hint.empty() ? "" : ", ", r.min, r.max);
        hint += text;
    }
    return hint;
}

constexpr double kDefaultMaxMegabytes = 16.0;

/// The file a field names, whole, within the input's size limit.
Result<std::string> readInput(const FormField& f, const Parameter& p) {
    const double maxMb = p.maximumMegabytes > 0.0 ? p.maximumMegabytes : kDefaultMaxMegabytes;
    return readTextFile(f.text, std::uintmax_t(maxMb * 1024.0 * 1024.0), "file for \"" + f.identifier + "\"");
}

}  // namespace

const char* toString(FieldWidget widget) {
    switch (widget) {
        case FieldWidget::Number: return "number";
        case FieldWidget::Integer: return "integer";
        case FieldWidget::Choice: return "choice";
        case FieldWidget::Toggle: return "toggle";
        case FieldWidget::Text: return "text";
        case FieldWidget::Area: return "area";
        case FieldWidget::Geometry: return "geometry";
        case FieldWidget::File: return "file";
    }
    return "text";
}

std::vector<FormField> makeForm(const ProcessDescription& process) {
    std::vector<FormField> form;
    for (const Parameter& p : process.inputs) {
        FormField f{.identifier = p.identifier, .title = p.title.empty() ? p.identifier : p.title, .abstract = p.abstract};
        f.required = p.minOccurs > 0;
        if (p.kind == DataKind::BoundingBox) {
            f.widget = FieldWidget::Area;
            f.crs = p.defaultCrs.empty() ? (p.crss.empty() ? "EPSG:4326" : p.crss.front()) : p.defaultCrs;
        } else if (p.kind == DataKind::Complex) {
            std::string mime = p.defaultFormat.mimeType;
            for (const Format& fmt : p.formats)
                if (isGeometryFormat(fmt.mimeType)) mime = fmt.mimeType;
            f.widget = isGeometryFormat(mime) ? FieldWidget::Geometry : FieldWidget::File;
            f.mimeType = f.widget == FieldWidget::Geometry ? mime : p.defaultFormat.mimeType;
        } else {
            const LiteralDomain& d = p.literal;
            const std::string type = lowerAscii(d.dataType);
            f.uom = d.uom;
            if (!d.anyValue && !d.values.empty()) {
                f.widget = FieldWidget::Choice;
                f.choices = d.values;
            } else if (type == "boolean") {
                f.widget = FieldWidget::Toggle;
            } else if (type == "integer" || type == "int" || type == "long" || type == "nonnegativeinteger" || type == "positiveinteger") {
                f.widget = FieldWidget::Integer;
            } else if (type == "float" || type == "double" || type == "decimal") {
                f.widget = FieldWidget::Number;
            }
            if (f.widget == FieldWidget::Number || f.widget == FieldWidget::Integer) {
                f.ranges = d.ranges;
                f.hint = rangeHint(d.ranges);
            }
            if (d.defaultValue) f.text = *d.defaultValue;
            else if (f.widget == FieldWidget::Choice) f.text = f.choices.front();
            else if (f.widget == FieldWidget::Toggle) f.text = "false";
        }
        // An optional input is sent when it has a default (the server would use it anyway).
        f.send = f.required || !f.text.empty();
        form.push_back(std::move(f));
    }
    return form;
}

bool bindPoint(std::vector<FormField>& fields, const std::array<double, 2>& lonLat) {
    bool bound = false;
    for (FormField& f : fields) {
        if (f.widget != FieldWidget::Number && f.widget != FieldWidget::Text) continue;
        const std::string id = lowerAscii(f.identifier);
        int axis = -1;
        if (id == "lon" || id == "longitude" || id == "x") axis = 0;
        else if (id == "lat" || id == "latitude" || id == "y") axis = 1;
        if (axis < 0) continue;
        char text[48];
        std::snprintf(text, sizeof text, "%.7f", lonLat[size_t(axis)]);
        f.text = text;
        f.send = true;
        bound = true;
    }
    return bound;
}

Result<std::vector<InputValue>> formInputs(const ProcessDescription& process, const std::vector<FormField>& fields,
                                           const FormGeometry& geometry) {
    std::vector<InputValue> inputs;
    std::string problems;
    const auto problem = [&](const FormField& f, const std::string& what) {
        problems += (problems.empty() ? "" : "; ") + ("\"" + f.identifier + "\": " + what);
    };
    for (const FormField& f : fields) {
        if (!f.send) continue;
        const Parameter* p = process.input(f.identifier);
        if (!p) {
            problem(f, "the process has no such input");
            continue;
        }
        InputValue v{.identifier = f.identifier, .kind = p->kind};
        switch (f.widget) {
            case FieldWidget::Area:
                if (!geometry.bounds) {
                    problem(f, "draw an area on the globe first (Measure: box or polygon)");
                    continue;
                }
                v.bbox = *geometry.bounds;
                v.crs = f.crs;
                break;
            case FieldWidget::Geometry:
                if (!f.text.empty()) {   // a layer's file instead of the drawing
                    auto data = readInput(f, *p);
                    if (!data) {
                        problem(f, data.message());
                        continue;
                    }
                    v.value = std::move(*data);
                    v.format = {.mimeType = f.mimeType};
                    break;
                }
                if (geometry.geoJson.empty()) {
                    problem(f, "draw its geometry on the globe first (Measure: a path, a polygon or a point)");
                    continue;
                }
                v.value = geometry.geoJson;
                v.format = {.mimeType = f.mimeType};
                break;
            case FieldWidget::File: {
                v.format = {.mimeType = f.mimeType};
                if (f.text.rfind("http://", 0) == 0 || f.text.rfind("https://", 0) == 0) {
                    v.reference = f.text;
                    break;
                }
                if (f.text.empty()) {
                    problem(f, "name a file or an http(s) address");
                    continue;
                }
                auto data = readInput(f, *p);
                if (!data) {
                    problem(f, data.message());
                    continue;
                }
                v.value = std::move(*data);
                if (v.format.mimeType.empty()) v.format.mimeType = mimeTypeFor(f.text);
                break;
            }
            default:
                v.value = f.text;
        }
        inputs.push_back(std::move(v));
    }
    if (!problems.empty()) return makeError(process.identifier + ": " + problems);
    if (auto ok = checkInputs(process, inputs); !ok) return ok.error();
    return inputs;
}

}  // namespace orbis::wps
