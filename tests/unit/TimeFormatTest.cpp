#include "base/TimeFormat.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

using namespace orbis;

namespace {

// 2026-03-20T08:00:00Z in Unix seconds (checked against Python's datetime).
constexpr TimeNs kMarch20 = 1'773'993'600 * kNsPerSecond;

TimeNs parseOk(std::string_view text) {
    auto r = parseIso8601(text);
    EXPECT_TRUE(r.ok()) << text << ": " << (r.ok() ? "" : r.message());
    return r.ok() ? *r : 0;
}

std::string parseError(std::string_view text) {
    auto r = parseIso8601(text);
    EXPECT_FALSE(r.ok()) << text << " was accepted as " << (r.ok() ? formatIso8601(*r, 9) : "");
    return r.ok() ? std::string() : r.message();
}

}  // namespace

TEST(TimeFormat, EpochParsesToZero) {
    EXPECT_EQ(parseOk("1970-01-01T00:00:00Z"), 0);
}

TEST(TimeFormat, ParsesUtcWithZ) {
    EXPECT_EQ(parseOk("2026-03-20T08:00:00Z"), kMarch20);
    EXPECT_EQ(parseOk("2026-03-20t08:00:00z"), kMarch20);
}

TEST(TimeFormat, ParsesNineFractionalDigitsToTheNanosecond) {
    EXPECT_EQ(parseOk("2026-03-20T08:00:00.123456789Z"), kMarch20 + 123'456'789);
}

TEST(TimeFormat, ParsesShortFractionAsDecimal) {
    EXPECT_EQ(parseOk("2026-03-20T08:00:00.5Z"), kMarch20 + 500'000'000);
    EXPECT_EQ(parseOk("2026-03-20T08:00:00,25Z"), kMarch20 + 250'000'000);
}

TEST(TimeFormat, PositiveOffsetIsSubtracted) {
    EXPECT_EQ(parseOk("2026-03-20T10:00:00+02:00"), kMarch20);
    EXPECT_EQ(parseOk("2026-03-20T10:00:00+0200"), kMarch20);
    EXPECT_EQ(parseOk("2026-03-20T10:00:00+02"), kMarch20);
}

TEST(TimeFormat, NegativeOffsetCrossesMidnight) {
    EXPECT_EQ(parseOk("2026-03-19T22:30:00-09:30"), kMarch20);
}

TEST(TimeFormat, SpaceMaySeparateDateAndTime) {
    EXPECT_EQ(parseOk("2026-03-20 08:00:00Z"), kMarch20);
}

TEST(TimeFormat, DateOnlyIsMidnightUtc) {
    EXPECT_EQ(parseOk("2026-03-20"), kMarch20 - 8 * 3600 * kNsPerSecond);
}

TEST(TimeFormat, SecondsMayBeOmitted) {
    EXPECT_EQ(parseOk("2026-03-20T08:00Z"), kMarch20);
}

TEST(TimeFormat, TimeWithoutOffsetIsUtc) {
    EXPECT_EQ(parseOk("2026-03-20T08:00:00"), kMarch20);
}

TEST(TimeFormat, LeapDayExistsOnlyInLeapYears) {
    EXPECT_EQ(parseOk("2024-02-29") + kNsPerDay, parseOk("2024-03-01"));
    EXPECT_EQ(parseOk("2000-02-29") + kNsPerDay, parseOk("2000-03-01"));  // divisible by 400
    EXPECT_NE(parseError("2026-02-29").find("February 2026 has 28 days"), std::string::npos);
    EXPECT_NE(parseError("1900-02-29").find("February 1900 has 28 days"), std::string::npos);  // century
    EXPECT_NE(parseError("2100-02-29").find("February 2100 has 28 days"), std::string::npos);
}

TEST(TimeFormat, RejectsMonth13QuotingTheText) {
    const std::string message = parseError("2026-13-01T00:00:00Z");
    EXPECT_NE(message.find("\"2026-13-01T00:00:00Z\""), std::string::npos) << message;
    EXPECT_NE(message.find("month 13"), std::string::npos) << message;
}

TEST(TimeFormat, RejectsFebruary30) {
    const std::string message = parseError("2026-02-30");
    EXPECT_NE(message.find("day 30"), std::string::npos) << message;
    EXPECT_NE(message.find("February 2026 has 28 days"), std::string::npos) << message;
}

TEST(TimeFormat, RejectsOutOfRangeClockFields) {
    EXPECT_NE(parseError("2026-03-20T25:00:00Z").find("hour 25"), std::string::npos);
    EXPECT_NE(parseError("2026-03-20T24:00:00Z").find("hour 24"), std::string::npos);
    EXPECT_NE(parseError("2026-03-20T08:60:00Z").find("minute 60"), std::string::npos);
    EXPECT_NE(parseError("2026-03-20T08:00:61Z").find("second 61"), std::string::npos);
    EXPECT_NE(parseError("2026-03-20T08:00:00+24:00").find("offset hour 24"), std::string::npos);
    EXPECT_NE(parseError("2026-03-20T08:00:00+01:60").find("offset minute 60"), std::string::npos);
}

TEST(TimeFormat, RejectsLeapSecond) {
    EXPECT_NE(parseError("2016-12-31T23:59:60Z").find("leap second"), std::string::npos);
}

TEST(TimeFormat, RejectsGarbage) {
    for (const char* text : {"", "hello", "2026", "2026-3-20", "2026/03/20", "20260320", "-2026-03-20", "2026-03-20T",
                             "2026-03-20X08:00:00", "2026-03-20T8:00:00Z", "2026-03-20T08:00:00.Z",
                             "2026-03-20T08:00:00Zjunk", "2026-03-20T08:00:00+2", " 2026-03-20", "2026-03-20 ",
                             "2026-03-20T08:00:00.1234567891Z"}) {
        const std::string message = parseError(text);
        EXPECT_NE(message.find("is not an ISO 8601 time"), std::string::npos) << text << ": " << message;
    }
}

TEST(TimeFormat, ErrorSaysWhatWasFoundWhere) {
    const std::string message = parseError("2026-03-20T08:00:00Zjunk");
    EXPECT_NE(message.find("'j' at position 21"), std::string::npos) << message;
}

TEST(TimeFormat, AcceptsYearsThatFitInt64NanosecondsOnly) {
    EXPECT_EQ(parseOk("1678-01-01"), daysFromCivil(1678, 1, 1) * kNsPerDay);
    EXPECT_EQ(parseOk("2261-12-31T23:59:59.999999999Z"), daysFromCivil(2262, 1, 1) * kNsPerDay - 1);
    EXPECT_NE(parseError("1677-12-31").find("year 1677"), std::string::npos);
    EXPECT_NE(parseError("2262-01-01").find("year 2262"), std::string::npos);
}

TEST(TimeFormat, FormatsMillisecondsByDefault) {
    EXPECT_EQ(formatIso8601(kMarch20), "2026-03-20T08:00:00.000Z");
    EXPECT_EQ(formatIso8601(kMarch20 + 123'456'789), "2026-03-20T08:00:00.123Z");
}

TEST(TimeFormat, FormatTruncatesInsteadOfRoundingUp) {
    // Rounding would print 08:00:01.000 for a time that is still in second 08:00:00.
    EXPECT_EQ(formatIso8601(kMarch20 + 999'999'999), "2026-03-20T08:00:00.999Z");
}

TEST(TimeFormat, FormatDigitCountIsClamped) {
    EXPECT_EQ(formatIso8601(kMarch20, 0), "2026-03-20T08:00:00Z");
    EXPECT_EQ(formatIso8601(kMarch20 + 5, 9), "2026-03-20T08:00:00.000000005Z");
    EXPECT_EQ(formatIso8601(kMarch20, -4), "2026-03-20T08:00:00Z");
    EXPECT_EQ(formatIso8601(kMarch20 + 5, 12), "2026-03-20T08:00:00.000000005Z");
}

TEST(TimeFormat, FormatsNegativeTimesBeforeTheEpoch) {
    EXPECT_EQ(formatIso8601(-1), "1969-12-31T23:59:59.999Z");
    EXPECT_EQ(formatIso8601(-1, 9), "1969-12-31T23:59:59.999999999Z");
    EXPECT_EQ(formatIso8601(-kNsPerDay), "1969-12-31T00:00:00.000Z");
    EXPECT_EQ(formatIso8601(-kNsPerSecond / 2, 1), "1969-12-31T23:59:59.5Z");
    EXPECT_EQ(formatIso8601(parseOk("1900-02-28T12:34:56.789Z")), "1900-02-28T12:34:56.789Z");
}

TEST(TimeFormat, FormatHandlesInt64Extremes) {
    EXPECT_EQ(formatIso8601(std::numeric_limits<TimeNs>::min(), 9), "1677-09-21T00:12:43.145224192Z");
    EXPECT_EQ(formatIso8601(std::numeric_limits<TimeNs>::max(), 9), "2262-04-11T23:47:16.854775807Z");
}

TEST(TimeFormat, FormatThenParseRoundTripsAcrossTheRange) {
    // A fixed LCG, so that a failure is reproducible.
    std::uint64_t state = 12345;
    const TimeNs lo = daysFromCivil(kMinYear, 1, 1) * kNsPerDay;
    const TimeNs hi = daysFromCivil(kMaxYear + 1, 1, 1) * kNsPerDay;
    for (int i = 0; i < 20000; ++i) {
        state = state * 6364136223846793005ULL + 1442695040888963407ULL;
        // hi - lo exceeds int64, so the offset is added in uint64 (C++20 converts back modulo 2^64).
        const std::uint64_t span = static_cast<std::uint64_t>(hi) - static_cast<std::uint64_t>(lo);
        const TimeNs t = static_cast<TimeNs>(static_cast<std::uint64_t>(lo) + state % span);
        const std::string text = formatIso8601(t, 9);
        auto parsed = parseIso8601(text);
        ASSERT_TRUE(parsed.ok()) << text;
        ASSERT_EQ(*parsed, t) << text;
    }
}

TEST(TimeFormat, ParseThenFormatRoundTripsLiterals) {
    for (const char* text : {"2026-03-20T08:00:00.000Z", "2024-02-29T23:59:59.999Z", "1970-01-01T00:00:00.000Z",
                             "1969-07-20T20:17:40.000Z", "2000-01-01T12:00:00.000Z"})
        EXPECT_EQ(formatIso8601(parseOk(text)), text);
}

TEST(TimeFormat, DaysFromCivilMatchesKnownDates) {
    EXPECT_EQ(daysFromCivil(1970, 1, 1), 0);
    EXPECT_EQ(daysFromCivil(2000, 3, 1), 11017);
    EXPECT_EQ(daysFromCivil(1900, 1, 1), -25567);
    EXPECT_EQ(daysFromCivil(1678, 1, 1), -106650);
}

TEST(TimeFormat, CivilFromDaysInvertsDaysFromCivilDayByDay) {
    // Walk every day of 1678..2261 and check that dates are consecutive and invert exactly.
    CivilDate prev = civilFromDays(daysFromCivil(1677, 12, 31));
    for (std::int64_t d = daysFromCivil(1678, 1, 1); d <= daysFromCivil(2261, 12, 31); ++d) {
        const CivilDate c = civilFromDays(d);
        ASSERT_EQ(daysFromCivil(c.year, c.month, c.day), d);
        ASSERT_GE(c.day, 1);
        ASSERT_LE(c.day, daysInMonth(c.year, c.month));
        const bool nextDay = c.year == prev.year && c.month == prev.month && c.day == prev.day + 1;
        const bool nextMonth = c.day == 1 && prev.day == daysInMonth(prev.year, prev.month) &&
                               ((c.year == prev.year && c.month == prev.month + 1) ||
                                (c.year == prev.year + 1 && c.month == 1 && prev.month == 12));
        ASSERT_TRUE(nextDay || nextMonth) << c.year << "-" << c.month << "-" << c.day;
        prev = c;
    }
}

TEST(TimeFormat, SecondsConversionRoundsToNearestNanosecond) {
    EXPECT_EQ(fromSeconds(1.5), 1'500'000'000);
    EXPECT_EQ(fromSeconds(-0.5), -500'000'000);
    EXPECT_EQ(fromSeconds(0.6e-9), 1);
    EXPECT_EQ(fromSeconds(0.4e-9), 0);
    EXPECT_EQ(fromSeconds(-1.25), -1'250'000'000);
    EXPECT_DOUBLE_EQ(toSeconds(-1'250'000'000), -1.25);
    EXPECT_DOUBLE_EQ(toSeconds(kMarch20), 1'773'993'600.0);
}

TEST(TimeFormat, SecondsRoundTripKeepsPresentDayPrecision) {
    // A double near 1.8e9 s has a spacing of 2^-22 s = 238 ns, so a round trip may move the time
    // by half of that; 120 ns is that bound.
    const TimeNs t = kMarch20 + 123'456'789;
    EXPECT_NEAR(static_cast<double>(fromSeconds(toSeconds(t)) - t), 0.0, 120.0);
}

TEST(TimeFormat, FromSecondsSaturatesAndMapsNanToZero) {
    EXPECT_EQ(fromSeconds(std::nan("")), 0);
    EXPECT_EQ(fromSeconds(1e300), std::numeric_limits<TimeNs>::max());
    EXPECT_EQ(fromSeconds(-1e300), std::numeric_limits<TimeNs>::min());
}

TEST(TimeFormat, ConversionsHandleInt64Extremes) {
    // 1e-6 relative: only the double rounding of a 19-digit number is at stake.
    const TimeNs lo = std::numeric_limits<TimeNs>::min(), hi = std::numeric_limits<TimeNs>::max();
    EXPECT_NEAR(toSeconds(lo), -9223372036.854775808, 1e-6);
    EXPECT_NEAR(toSeconds(hi), 9223372036.854775807, 1e-6);
    EXPECT_NEAR(daysSinceJ2000(lo), -9223372036.854775808 / 86400.0 - 10957.5, 1e-6);
    EXPECT_NEAR(daysSinceJ2000(hi), 9223372036.854775807 / 86400.0 - 10957.5, 1e-6);
}

TEST(TimeFormat, JulianDateMatchesReferenceEpochs) {
    // Both epochs are exactly representable, so the comparison is exact.
    EXPECT_EQ(julianDateUtc(0), 2440587.5);
    EXPECT_EQ(julianDateUtc(parseOk("2000-01-01T12:00:00Z")), 2451545.0);
    EXPECT_EQ(daysSinceJ2000(parseOk("2000-01-01T12:00:00Z")), 0.0);
    EXPECT_EQ(daysSinceJ2000(parseOk("1999-12-31T00:00:00Z")), -1.5);
}

TEST(TimeFormat, JulianDateKeepsSubSecondPrecision) {
    // A JD near 2.46e6 has a spacing of 4.7e-10 days (40 us); 1e-9 days (86 us) covers rounding.
    const double jd = julianDateUtc(kMarch20 + kNsPerSecond / 2);
    EXPECT_NEAR(jd, 2461119.5 + 8.0 / 24.0 + 0.5 / 86400.0, 1e-9);
}
