#include "tools/orbis/Plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace orbis::cli {
namespace {

// 3x5 glyphs, one row per 3 bits (MSB left): digits, capitals (lower case drawn as capitals)
// and a little punctuation.
const char* glyph(char c) {
    if (c >= 'a' && c <= 'z') c = char(c - 'a' + 'A');
    switch (c) {
        case '0': return "\x07\x05\x05\x05\x07";
        case '1': return "\x02\x06\x02\x02\x07";
        case '2': return "\x07\x01\x07\x04\x07";
        case '3': return "\x07\x01\x07\x01\x07";
        case '4': return "\x05\x05\x07\x01\x01";
        case '5': return "\x07\x04\x07\x01\x07";
        case '6': return "\x07\x04\x07\x05\x07";
        case '7': return "\x07\x01\x01\x01\x01";
        case '8': return "\x07\x05\x07\x05\x07";
        case '9': return "\x07\x05\x07\x01\x07";
        case '.': return "\x00\x00\x00\x00\x02";
        case '-': return "\x00\x00\x07\x00\x00";
        case '=': return "\x00\x07\x00\x07\x00";
        case 'A': return "\x02\x05\x07\x05\x05";
        case 'B': return "\x06\x05\x06\x05\x06";
        case 'C': return "\x03\x04\x04\x04\x03";
        case 'D': return "\x06\x05\x05\x05\x06";
        case 'E': return "\x07\x04\x06\x04\x07";
        case 'F': return "\x07\x04\x06\x04\x04";
        case 'G': return "\x03\x04\x05\x05\x03";
        case 'H': return "\x05\x05\x07\x05\x05";
        case 'I': return "\x07\x02\x02\x02\x07";
        case 'J': return "\x01\x01\x01\x05\x02";
        case 'K': return "\x05\x05\x06\x05\x05";
        case 'L': return "\x04\x04\x04\x04\x07";
        case 'M': return "\x05\x07\x07\x05\x05";
        case 'N': return "\x06\x05\x05\x05\x05";
        case 'O': return "\x02\x05\x05\x05\x02";
        case 'P': return "\x06\x05\x06\x04\x04";
        case 'Q': return "\x02\x05\x05\x06\x03";
        case 'R': return "\x06\x05\x06\x05\x05";
        case 'S': return "\x03\x04\x02\x01\x06";
        case 'T': return "\x07\x02\x02\x02\x02";
        case 'U': return "\x05\x05\x05\x05\x07";
        case 'V': return "\x05\x05\x05\x05\x02";
        case 'W': return "\x05\x05\x07\x07\x05";
        case 'X': return "\x05\x05\x02\x05\x05";
        case 'Y': return "\x05\x05\x02\x02\x02";
        case 'Z': return "\x07\x01\x02\x04\x07";
        case '/': return "\x01\x01\x02\x04\x04";
        case '%': return "\x05\x01\x02\x04\x05";
        case '(': return "\x02\x04\x04\x04\x02";
        case ')': return "\x02\x01\x01\x01\x02";
        case ':': return "\x00\x02\x00\x02\x00";
        case ',': return "\x00\x00\x00\x02\x04";
        case '+': return "\x00\x02\x07\x02\x00";
        default: return "\x00\x00\x00\x00\x00";
    }
}

struct Canvas {
    ImageRgba8& img;
    void set(int x, int y, uint8_t r, uint8_t g, uint8_t b) {
        if (x < 0 || y < 0 || x >= int(img.width) || y >= int(img.height)) return;
        uint8_t* p = &img.pixels[(size_t(y) * img.width + size_t(x)) * 4];
        p[0] = r, p[1] = g, p[2] = b, p[3] = 255;
    }
    void line(int x0, int y0, int x1, int y1, uint8_t r, uint8_t g, uint8_t b) {
        const int dx = std::abs(x1 - x0), dy = -std::abs(y1 - y0), sx = x0 < x1 ? 1 : -1, sy = y0 < y1 ? 1 : -1;
        int err = dx + dy;
        for (;;) {
            set(x0, y0, r, g, b);
            if (x0 == x1 && y0 == y1) break;
            const int e2 = 2 * err;
            if (e2 >= dy) err += dy, x0 += sx;
            if (e2 <= dx) err += dx, y0 += sy;
        }
    }
    void text(int x, int y, const std::string& s, int scale = 2) {
        for (char c : s) {
            const char* g = glyph(c);
            for (int row = 0; row < 5; ++row)
                for (int col = 0; col < 3; ++col)
                    if (g[row] & (4 >> col))
                        for (int a = 0; a < scale; ++a)
                            for (int b = 0; b < scale; ++b) set(x + col * scale + a, y + row * scale + b, 20, 20, 20);
            x += 4 * scale;
        }
    }
};

std::string number(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, v >= 100 ? "%.0f" : v >= 10 ? "%.1f" : "%.2f", v);
    return buf;
}

}  // namespace

ImageRgba8 plotPoints(const std::vector<PlotPoint>& points, uint32_t width, uint32_t height) {
    ImageRgba8 img{width, height, std::vector<uint8_t>(size_t(width) * height * 4, 255)};
    Canvas c{img};
    const int left = 60, right = int(width) - 20, top = 20, bottom = int(height) - 40;
    double maxX = 0, maxY = 0;
    for (const auto& p : points) maxX = std::max(maxX, p.x), maxY = std::max(maxY, p.y);
    maxX = maxX > 0 ? maxX * 1.1 : 1.0;
    maxY = maxY > 0 ? maxY * 1.1 : 1.0;
    c.line(left, bottom, right, bottom, 0, 0, 0);   // x axis: ms per frame
    c.line(left, bottom, left, top, 0, 0, 0);       // y axis: error (RMSE)
    c.text(right - 60, bottom + 12, number(maxX));
    c.text(4, top, number(maxY));
    c.text(left - 12, bottom + 12, "0");
    const auto px = [&](double x) { return left + int(std::lround((right - left) * x / maxX)); };
    const auto py = [&](double y) { return bottom - int(std::lround((bottom - top) * y / maxY)); };
    for (size_t i = 1; i < points.size(); ++i)
        c.line(px(points[i - 1].x), py(points[i - 1].y), px(points[i].x), py(points[i].y), 40, 90, 200);
    for (const auto& p : points) {
        for (int a = -3; a <= 3; ++a)
            for (int b = -3; b <= 3; ++b) c.set(px(p.x) + a, py(p.y) + b, 200, 40, 40);
        c.text(px(p.x) + 6, py(p.y) - 14, p.label);
    }
    return img;
}

ImageRgba8 plotPanels(const std::vector<PlotSeries>& panels, const std::string& xTitle, uint32_t width,
                      uint32_t panelHeight) {
    const uint32_t height = panelHeight * uint32_t(std::max<size_t>(panels.size(), 1)) + 30;
    ImageRgba8 img{width, height, std::vector<uint8_t>(size_t(width) * height * 4, 255)};
    Canvas c{img};
    const int left = 70, right = int(width) - 20;
    double maxX = 0;
    for (const auto& panel : panels)
        for (const auto& [x, y] : panel.points) maxX = std::max(maxX, x);
    if (!(maxX > 0)) maxX = 1.0;
    const auto px = [&](double x) { return left + int(std::lround((right - left) * x / maxX)); };
    for (size_t k = 0; k < panels.size(); ++k) {
        const auto& panel = panels[k];
        const int top = int(k * panelHeight) + 24, bottom = int((k + 1) * panelHeight) - 6;
        double maxY = 0;
        for (const auto& [x, y] : panel.points) maxY = std::max(maxY, y);
        maxY = maxY > 0 ? maxY * 1.1 : 1.0;
        const auto py = [&](double y) { return bottom - int(std::lround((bottom - top) * y / maxY)); };
        c.line(left, bottom, right, bottom, 0, 0, 0);
        c.line(left, bottom, left, top, 0, 0, 0);
        c.text(left, top - 18, panel.title);
        c.text(4, top, number(maxY));
        c.text(left - 12, bottom - 10, "0");
        for (size_t i = 1; i < panel.points.size(); ++i)
            c.line(px(panel.points[i - 1].first), py(panel.points[i - 1].second), px(panel.points[i].first),
                   py(panel.points[i].second), 40, 90, 200);
    }
    const int axis = int(height) - 22;
    c.text(left - 4, axis, "0");
    c.text(right - 40, axis, number(maxX));
    c.text((left + right) / 2 - int(xTitle.size()) * 4, axis, xTitle);
    return img;
}

}  // namespace orbis::cli
