#pragma once
// The form the Processes panel builds from a process description: one field per input, with
// the widget that fits it (a number within its ranges, a whole number, a choice among the
// allowed values, a toggle, text, an area, a geometry, a file or address), its default, and
// whether it is sent; then the Execute inputs from the fields and the geometry drawn on the
// globe (boxes from its bounds, GeoJSON complex inputs from its shape, inputs named lon/lat or
// longitude/latitude from its point). No ImGui: the panel draws the fields, this file holds
// their meaning, so that it is tested and fuzzed without a window.

#include "formats/wps/WpsDocuments.h"

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace orbis::wps {

enum class FieldWidget { Number, Integer, Choice, Toggle, Text, Area, Geometry, File };
const char* toString(FieldWidget widget);

struct FormField {
    std::string identifier, title, abstract;
    FieldWidget widget = FieldWidget::Text;
    bool required = true;
    bool send = true;                    ///< optional inputs are sent only when ticked (or given a default)
    std::string text;                    ///< the value as typed (numbers too; a toggle "true"/"false"; a file's path or an http(s) address)
    std::vector<std::string> choices;    ///< Choice
    std::vector<ValueRange> ranges;      ///< Number, Integer: the allowed ranges (none: any)
    std::string uom;
    std::string mimeType;                ///< Geometry, File: the format it is sent as
    std::string crs;                     ///< Area
    /// Number, Integer: what the value should be near ("" none); shown as a hint.
    std::string hint;
};

/// The geometry drawn on the globe, as the form takes it.
struct FormGeometry {
    /// West, south, east, north; none without points.
    std::optional<std::array<double, 4>> bounds;
    /// The shape as a GeoJSON FeatureCollection; empty while incomplete.
    std::string geoJson;
    /// The first point (lon, lat); none without points.
    std::optional<std::array<double, 2>> point;
};

/// One field per input of `process`, in order, with its default.
std::vector<FormField> makeForm(const ProcessDescription& process);

/// Fields whose identifier names a longitude or a latitude ("lon", "longitude", "x" with "y",
/// any case) take the point's; true when one did.
bool bindPoint(std::vector<FormField>& fields, const std::array<double, 2>& lonLat);

/// The Execute inputs from the fields: Area fields take the geometry's bounds, Geometry fields
/// its GeoJSON, or the file their text names (a vector layer's data) when it names one (both
/// required to be drawn or named when the field is sent), File fields read the file
/// named (at most the input's maximumMegabytes, else 16 MB) or send an http(s) address as a
/// reference. Every problem in one message, naming the field; the rest of the checks are
/// checkInputs' (types, ranges, allowed values), which this calls.
Result<std::vector<InputValue>> formInputs(const ProcessDescription& process, const std::vector<FormField>& fields,
                                           const FormGeometry& geometry);

}  // namespace orbis::wps
