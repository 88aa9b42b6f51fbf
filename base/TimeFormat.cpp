#include "base/TimeFormat.h"

#include <cmath>
#include <cstdio>
#include <limits>

namespace orbis {
namespace {

constexpr TimeNs kNsPerMinute = 60 * kNsPerSecond;
constexpr TimeNs kNsPerHour = 60 * kNsPerMinute;

// J2000.0 (JD 2451545.0) is 2000-01-01T12:00:00Z: 10957 days and a half after the epoch.
constexpr TimeNs kJ2000Days = 10957;
constexpr double kJulianDateAtJ2000 = 2451545.0;

constexpr const char* kMonthNames[12] = {"January", "February", "March",     "April",   "May",      "June",
                                         "July",    "August",   "September", "October", "November", "December"};

// Floor division and its non-negative remainder: C++ '/' truncates toward zero, which would put
// t = -1 ns into 1970-01-01 instead of 1969-12-31.
// Both are written with / and % only, so that they cannot overflow even for INT64_MIN (b > 0).
constexpr TimeNs floorDiv(TimeNs a, TimeNs b) { return a / b - (a % b < 0 ? 1 : 0); }
constexpr TimeNs floorMod(TimeNs a, TimeNs b) { return a % b < 0 ? a % b + b : a % b; }

// A cursor over the text with the error wording in one place.
class Parser {
public:
    explicit Parser(std::string_view text) : text_(text) {}

    bool atEnd() const { return pos_ == text_.size(); }
    char peek() const { return atEnd() ? '\0' : text_[pos_]; }
    void skip() { ++pos_; }
    size_t position() const { return pos_; }

    bool accept(char c) {
        if (peek() != c) return false;
        ++pos_;
        return true;
    }

    /// Reads exactly `count` decimal digits.
    bool digits(int count, int& out) {
        int value = 0;
        for (int i = 0; i < count; ++i) {
            const char c = peek();
            if (c < '0' || c > '9') return false;
            value = value * 10 + (c - '0');
            ++pos_;
        }
        out = value;
        return true;
    }

    /// Describes what stands at the cursor, for "expected X but found Y" messages.
    std::string found() const {
        if (atEnd()) return "the end of the text";
        // Appended piece by piece: GCC 12 warns falsely (-Wrestrict) on the chained operator+.
        std::string s = "'";
        s += text_[pos_];
        s += "' at position ";
        s += std::to_string(pos_ + 1);
        return s;
    }

    Error fail(const std::string& what) const {
        // Long inputs are shortened so that a pasted paragraph does not flood the log.
        constexpr size_t kMaxQuoted = 64;
        std::string quoted(text_.substr(0, kMaxQuoted));
        if (text_.size() > kMaxQuoted) quoted += "...";
        return makeError("\"" + quoted + "\" is not an ISO 8601 time: " + what);
    }

private:
    std::string_view text_;
    size_t pos_ = 0;
};

std::string twoDigits(int v) {
    char buf[16];
    std::snprintf(buf, sizeof buf, "%02d", v);
    return buf;
}

}  // namespace

std::int64_t daysFromCivil(int year, int month, int day) {
    // Hinnant: shift the year to start in March so that the leap day is the last day of the
    // "year", then count 400-year eras of 146097 days.
    const std::int64_t y = static_cast<std::int64_t>(year) - (month <= 2 ? 1 : 0);
    const std::int64_t era = (y >= 0 ? y : y - 399) / 400;
    const std::int64_t yoe = y - era * 400;                                      // [0, 399]
    const std::int64_t mp = month > 2 ? month - 3 : month + 9;                   // [0, 11], March = 0
    const std::int64_t doy = (153 * mp + 2) / 5 + day - 1;                       // [0, 365]
    const std::int64_t doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;              // [0, 146096]
    return era * 146097 + doe - 719468;  // 719468 = days from 0000-03-01 to 1970-01-01
}

CivilDate civilFromDays(std::int64_t days) {
    const std::int64_t z = days + 719468;
    const std::int64_t era = (z >= 0 ? z : z - 146096) / 146097;
    const std::int64_t doe = z - era * 146097;                                   // [0, 146096]
    const std::int64_t yoe = (doe - doe / 1460 + doe / 36524 - doe / 146096) / 365;  // [0, 399]
    const std::int64_t doy = doe - (365 * yoe + yoe / 4 - yoe / 100);            // [0, 365]
    const std::int64_t mp = (5 * doy + 2) / 153;                                 // [0, 11]
    CivilDate date;
    date.day = static_cast<int>(doy - (153 * mp + 2) / 5 + 1);
    date.month = static_cast<int>(mp < 10 ? mp + 3 : mp - 9);
    date.year = static_cast<int>(yoe + era * 400 + (date.month <= 2 ? 1 : 0));
    return date;
}

int daysInMonth(int year, int month) {
    static constexpr int kDays[12] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
    if (month < 1 || month > 12) return 0;
    const bool leap = (year % 4 == 0 && year % 100 != 0) || year % 400 == 0;
    return month == 2 && leap ? 29 : kDays[month - 1];
}

Result<TimeNs> parseIso8601(std::string_view text) {
    Parser p(text);
    if (text.empty()) return p.fail("the text is empty");

    int year = 0, month = 0, day = 0;
    if (p.peek() == '+' || p.peek() == '-') return p.fail("signed (expanded) years are not supported");
    if (!p.digits(4, year)) return p.fail("expected a 4-digit year (YYYY-MM-DD) but found " + p.found());
    if (!p.accept('-')) return p.fail("expected '-' after the year but found " + p.found());
    if (!p.digits(2, month)) return p.fail("expected a 2-digit month but found " + p.found());
    if (!p.accept('-')) return p.fail("expected '-' after the month but found " + p.found());
    if (!p.digits(2, day)) return p.fail("expected a 2-digit day but found " + p.found());

    if (year < kMinYear || year > kMaxYear)
        return p.fail("year " + std::to_string(year) + " is outside " + std::to_string(kMinYear) + ".." +
                      std::to_string(kMaxYear) + " (the range of 64-bit nanoseconds)");
    if (month < 1 || month > 12) return p.fail("month " + twoDigits(month) + " is not in 01..12");
    const int monthDays = daysInMonth(year, month);
    if (day < 1 || day > monthDays)
        return p.fail("day " + twoDigits(day) + " does not exist: " + kMonthNames[month - 1] + " " +
                      std::to_string(year) + " has " + std::to_string(monthDays) + " days");

    // Every field below is range-checked and the year is within kMinYear..kMaxYear, so the sum
    // cannot overflow: the extreme (1678-01-01T00:00+23:59) is still after 1677-09-21.
    TimeNs t = daysFromCivil(year, month, day) * kNsPerDay;
    if (p.atEnd()) return t;

    if (!(p.accept('T') || p.accept('t') || p.accept(' ')))
        return p.fail("expected 'T' or a space after the date but found " + p.found());

    int hour = 0, minute = 0, second = 0;
    if (!p.digits(2, hour)) return p.fail("expected a 2-digit hour but found " + p.found());
    if (!p.accept(':')) return p.fail("expected ':' after the hour but found " + p.found());
    if (!p.digits(2, minute)) return p.fail("expected 2-digit minutes but found " + p.found());
    TimeNs fraction = 0;
    if (p.accept(':')) {
        if (!p.digits(2, second)) return p.fail("expected 2-digit seconds but found " + p.found());
        if (p.peek() == '.' || p.peek() == ',') {  // ISO 8601 allows both decimal signs
            p.skip();
            int count = 0;
            TimeNs scale = kNsPerSecond;
            while (p.peek() >= '0' && p.peek() <= '9') {
                if (++count > 9) return p.fail("more than 9 fractional digits (finer than a nanosecond)");
                scale /= 10;
                fraction += (p.peek() - '0') * scale;
                p.skip();
            }
            if (count == 0) return p.fail("expected digits after the decimal sign but found " + p.found());
        }
    }
    if (hour > 23) return p.fail("hour " + twoDigits(hour) + " is not in 00..23");
    if (minute > 59) return p.fail("minute " + twoDigits(minute) + " is not in 00..59");
    if (second == 60) return p.fail("second 60 (a leap second) is not supported: orbis time has no leap seconds");
    if (second > 59) return p.fail("second " + twoDigits(second) + " is not in 00..59");
    t += hour * kNsPerHour + minute * kNsPerMinute + second * kNsPerSecond + fraction;

    if (p.accept('Z') || p.accept('z')) {
        // UTC
    } else if (p.peek() == '+' || p.peek() == '-') {
        const int sign = p.peek() == '+' ? 1 : -1;
        p.skip();
        int offsetHours = 0, offsetMinutes = 0;
        if (!p.digits(2, offsetHours)) return p.fail("expected a 2-digit offset hour but found " + p.found());
        const bool colon = p.accept(':');
        if (colon || (p.peek() >= '0' && p.peek() <= '9')) {
            if (!p.digits(2, offsetMinutes))
                return p.fail("expected 2-digit offset minutes but found " + p.found());
        }
        if (offsetHours > 23) return p.fail("offset hour " + twoDigits(offsetHours) + " is not in 00..23");
        if (offsetMinutes > 59) return p.fail("offset minute " + twoDigits(offsetMinutes) + " is not in 00..59");
        // Local time = UTC + offset, so UTC = local - offset.
        t -= sign * (offsetHours * kNsPerHour + offsetMinutes * kNsPerMinute);
    }
    if (!p.atEnd()) return p.fail("unexpected " + p.found() + " after the time");
    return t;
}

std::string formatIso8601(TimeNs t, int fractionDigits) {
    if (fractionDigits < 0) fractionDigits = 0;
    if (fractionDigits > 9) fractionDigits = 9;
    const TimeNs seconds = floorDiv(t, kNsPerSecond);
    const TimeNs nanos = floorMod(t, kNsPerSecond);  // [0, 1e9)
    const TimeNs days = floorDiv(seconds, 86'400);
    const TimeNs secondOfDay = seconds - days * 86'400;
    const CivilDate date = civilFromDays(days);

    char buf[48];
    int n = std::snprintf(buf, sizeof buf, "%04d-%02d-%02dT%02d:%02d:%02d", date.year, date.month, date.day,
                          static_cast<int>(secondOfDay / 3600), static_cast<int>(secondOfDay / 60 % 60),
                          static_cast<int>(secondOfDay % 60));
    if (fractionDigits > 0) {
        TimeNs divisor = 1;
        for (int i = fractionDigits; i < 9; ++i) divisor *= 10;
        n += std::snprintf(buf + n, sizeof buf - n, ".%0*lld", fractionDigits,
                           static_cast<long long>(nanos / divisor));
    }
    std::snprintf(buf + n, sizeof buf - n, "Z");
    return buf;
}

double toSeconds(TimeNs t) {
    return static_cast<double>(floorDiv(t, kNsPerSecond)) + static_cast<double>(floorMod(t, kNsPerSecond)) * 1e-9;
}

TimeNs fromSeconds(double seconds) {
    if (std::isnan(seconds)) return 0;
    // 9.2e9 s is the edge of the int64 ns range; saturate rather than invoke undefined behaviour.
    constexpr double kLimit = 9.2e9;
    if (seconds >= kLimit) return std::numeric_limits<TimeNs>::max();
    if (seconds <= -kLimit) return std::numeric_limits<TimeNs>::min();
    // Whole seconds and the fraction separately: seconds * 1e9 in one go would lose the low
    // nanoseconds of present-day times (a double has 53 bits, present-day ns need 61).
    const double whole = std::floor(seconds);
    const double fraction = seconds - whole;  // exact for seconds >= 1 (Sterbenz), else within 1e-16 s
    return static_cast<TimeNs>(whole) * kNsPerSecond + static_cast<TimeNs>(std::llround(fraction * 1e9));
}

double daysSinceJ2000(TimeNs t) {
    // Whole days first, so that t - J2000 cannot overflow near the ends of the int64 range.
    const TimeNs days = floorDiv(t, kNsPerDay);
    const TimeNs nsOfDay = floorMod(t, kNsPerDay);
    return static_cast<double>(days - kJ2000Days) +
           static_cast<double>(nsOfDay - kNsPerDay / 2) / static_cast<double>(kNsPerDay);
}

double julianDateUtc(TimeNs t) { return kJulianDateAtJ2000 + daysSinceJ2000(t); }

}  // namespace orbis
