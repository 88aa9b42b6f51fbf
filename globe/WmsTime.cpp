#include "globe/WmsTime.h"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <optional>

namespace orbis::globe {
namespace {

struct Period {
    int64_t years = 0, months = 0, days = 0;
    int64_t seconds = 0;   ///< hours, minutes and seconds
    bool zero() const { return years == 0 && months == 0 && days == 0 && seconds == 0; }
};

std::string trim(std::string_view s) {
    size_t a = 0, b = s.size();
    while (a < b && std::isspace(static_cast<unsigned char>(s[a]))) ++a;
    while (b > a && std::isspace(static_cast<unsigned char>(s[b - 1]))) --b;
    return std::string(s.substr(a, b - a));
}

/// P[nY][nM][nW][nD][T[nH][nM][nS]]: whole numbers only.
std::optional<Period> parsePeriod(std::string_view p) {
    if (p.size() < 3 || (p[0] != 'P' && p[0] != 'p')) return std::nullopt;
    Period out;
    bool time = false, any = false;
    for (size_t i = 1; i < p.size();) {
        if (p[i] == 'T' || p[i] == 't') {
            if (time) return std::nullopt;
            time = true;
            ++i;
            continue;
        }
        int64_t n = 0;
        size_t digits = 0;
        while (i < p.size() && std::isdigit(static_cast<unsigned char>(p[i])) && digits < 9) n = n * 10 + (p[i++] - '0'), ++digits;
        if (digits == 0 || i >= p.size()) return std::nullopt;
        const char unit = char(std::toupper(static_cast<unsigned char>(p[i++])));
        if (!time && unit == 'Y') out.years += n;
        else if (!time && unit == 'M') out.months += n;
        else if (!time && unit == 'W') out.days += 7 * n;
        else if (!time && unit == 'D') out.days += n;
        else if (time && unit == 'H') out.seconds += 3600 * n;
        else if (time && unit == 'M') out.seconds += 60 * n;
        else if (time && unit == 'S') out.seconds += n;
        else return std::nullopt;
        any = true;
    }
    if (!any || out.zero()) return std::nullopt;
    return out;
}

/// `start` moved by `k` whole periods (calendar months and years from the start's date, the day
/// clamped to the month's length); nothing when the result falls outside what TimeNs holds
/// (about 1678 to 2261), so a huge period ends the interval instead of overflowing.
std::optional<TimeNs> advance(TimeNs start, const Period& p, int64_t k) {
    const int64_t days = start >= 0 ? start / kNsPerDay : -((-start + kNsPerDay - 1) / kNsPerDay);
    const TimeNs ofDay = start - days * kNsPerDay;
    const CivilDate d = civilFromDays(days);
    int64_t months = 0, step = 0;
    if (__builtin_mul_overflow(p.years, int64_t(12), &step) || __builtin_add_overflow(step, p.months, &step) ||
        __builtin_mul_overflow(k, step, &step) || __builtin_add_overflow(int64_t(d.year) * 12 + (d.month - 1), step, &months))
        return std::nullopt;
    const int64_t year64 = months >= 0 ? months / 12 : -((-months + 11) / 12);
    if (year64 < 1600 || year64 > 2300) return std::nullopt;
    const int year = int(year64);
    const int month = int(months - year64 * 12) + 1;
    const int day = std::min(d.day, daysInMonth(year, month));
    int64_t allDays = 0, ns = 0, secs = 0, secNs = 0;
    if (__builtin_mul_overflow(k, p.days, &allDays) || __builtin_add_overflow(allDays, int64_t(daysFromCivil(year, month, day)), &allDays) ||
        __builtin_mul_overflow(allDays, kNsPerDay, &ns) || __builtin_add_overflow(ns, ofDay, &ns) ||
        __builtin_mul_overflow(k, p.seconds, &secs) || __builtin_mul_overflow(secs, kNsPerSecond, &secNs) ||
        __builtin_add_overflow(ns, secNs, &ns))
        return std::nullopt;
    return ns;
}

}  // namespace

Result<std::vector<WmsTimeValue>> parseWmsTimeExtent(std::string_view extent) {
    std::vector<WmsTimeValue> out;
    const std::string all = trim(extent);
    if (all.empty()) return makeError("the time extent is empty");
    size_t from = 0;
    while (from <= all.size()) {
        const size_t comma = std::min(all.find(',', from), all.size());
        const std::string part = trim(std::string_view(all).substr(from, comma - from));
        from = comma + 1;
        if (part.empty()) return makeError("time extent \"" + all + "\": an empty value between commas");
        const size_t slash = part.find('/');
        if (slash == std::string::npos) {
            auto t = parseIso8601(part);
            if (!t) return makeError("time extent \"" + all + "\": " + t.message());
            out.push_back({part, *t});
        } else {
            const size_t slash2 = part.find('/', slash + 1);
            if (slash2 == std::string::npos)
                return makeError("time extent \"" + all + "\": the interval \"" + part + "\" has no period (start/end/period, such as P1D)");
            const std::string a = trim(part.substr(0, slash)), b = trim(part.substr(slash + 1, slash2 - slash - 1));
            const std::string pp = trim(part.substr(slash2 + 1));
            auto start = parseIso8601(a);
            if (!start) return makeError("time extent \"" + all + "\": " + start.message());
            auto end = parseIso8601(b);
            if (!end) return makeError("time extent \"" + all + "\": " + end.message());
            if (*end < *start) return makeError("time extent \"" + all + "\": the interval \"" + part + "\" ends before it starts");
            const auto period = parsePeriod(pp);
            if (!period)
                return makeError("time extent \"" + all + "\": \"" + pp + "\" is not an ISO 8601 period of whole units (such as P1M, P1D, PT6H)");
            const bool dateOnly = a.size() == 10;
            for (int64_t k = 0;; ++k) {
                const auto next = advance(*start, *period, k);
                if (!next || *next > *end) break;
                const TimeNs t = *next;
                if (out.size() >= kMaxWmsTimeValues)
                    return makeError("time extent \"" + all + "\": more than " + std::to_string(kMaxWmsTimeValues) + " values");
                out.push_back({dateOnly ? formatIso8601(t, 0).substr(0, 10) : formatIso8601(t, 0), t});
            }
        }
        if (out.size() > kMaxWmsTimeValues)
            return makeError("time extent \"" + all + "\": more than " + std::to_string(kMaxWmsTimeValues) + " values");
        if (comma >= all.size()) break;
    }
    std::stable_sort(out.begin(), out.end(), [](const WmsTimeValue& x, const WmsTimeValue& y) { return x.at < y.at; });
    out.erase(std::unique(out.begin(), out.end(), [](const WmsTimeValue& x, const WmsTimeValue& y) { return x.at == y.at; }), out.end());
    return out;
}

size_t wmsTimeIndexAt(std::span<const WmsTimeValue> values, TimeNs t) {
    const auto it = std::upper_bound(values.begin(), values.end(), t, [](TimeNs v, const WmsTimeValue& x) { return v < x.at; });
    return it == values.begin() ? 0 : size_t(it - values.begin()) - 1;
}

}  // namespace orbis::globe
