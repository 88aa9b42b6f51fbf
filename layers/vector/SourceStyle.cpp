#include "layers/vector/SourceStyle.h"

#include <ogr_featurestyle.h>

#include <memory>

namespace orbis::vector {
namespace {

std::optional<glm::dvec4> color(const char* text, GBool isDefault) {
    int r = 0, g = 0, b = 0, a = 255;
    if (isDefault || !text || !OGRStyleTool::GetRGBFromString(text, r, g, b, a)) return std::nullopt;
    return glm::dvec4(r, g, b, a) / 255.0;
}

std::optional<double> positive(double value, GBool isDefault) {
    if (isDefault || !(value > 0.0) || !(value < 1e6)) return std::nullopt;
    return value;
}

}  // namespace

SourceStyle parseOgrStyle(const std::string& styleString) {
    SourceStyle out;
    if (styleString.empty()) return out;
    OGRStyleMgr manager;
    if (!manager.InitStyleString(styleString.c_str())) return out;
    // Each getter says through its argument whether the string gave the value.
    const auto colorOf = [](auto&& get) {
        GBool isDefault = TRUE;
        const char* text = get(isDefault);
        return color(text, isDefault);
    };
    const auto sizeOf = [](auto&& get) {
        GBool isDefault = TRUE;
        const double value = get(isDefault);
        return positive(value, isDefault);
    };
    for (int i = 0; i < manager.GetPartCount(); ++i) {
        std::unique_ptr<OGRStyleTool> tool(manager.GetPart(i));
        if (!tool) continue;
        switch (tool->GetType()) {
            case OGRSTCPen: {
                auto& pen = static_cast<OGRStylePen&>(*tool);
                pen.SetUnit(OGRSTUPixel, 1.0);   // widths come in px, pt, mm...
                out.lineColor = colorOf([&](GBool& d) { return pen.Color(d); });
                out.lineWidthPx = sizeOf([&](GBool& d) { return pen.Width(d); });
                break;
            }
            case OGRSTCBrush: {
                auto& brush = static_cast<OGRStyleBrush&>(*tool);
                out.fillColor = colorOf([&](GBool& d) { return brush.ForeColor(d); });
                break;
            }
            case OGRSTCSymbol: {
                auto& symbol = static_cast<OGRStyleSymbol&>(*tool);
                GBool isDefault = TRUE;
                const char* id = symbol.Id(isDefault);
                if (!isDefault && id && *id) out.icon = id;
                // KML's IconStyle scale, as a plain number (no unit to convert).
                out.iconScale = sizeOf([&](GBool& d) { return symbol.Size(d); });
                out.iconColor = colorOf([&](GBool& d) { return symbol.Color(d); });
                break;
            }
            case OGRSTCLabel: {
                auto& label = static_cast<OGRStyleLabel&>(*tool);
                out.labelColor = colorOf([&](GBool& d) { return label.ForeColor(d); });
                // KML's LabelStyle scale arrives as a stretch in percent.
                if (auto stretch = sizeOf([&](GBool& d) { return label.Stretch(d); })) out.labelScale = *stretch / 100.0;
                break;
            }
            default: break;
        }
    }
    return out;
}

}  // namespace orbis::vector
